#include "models/stability/stability.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "models/stability/dob_design.h"

namespace mb {

namespace {

using Complex = std::complex<double>;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The discrete filters of the loop, as the blocks build them.
struct DiscreteLoop {
  DiscreteTf plant, pd, feedforward, q, q_nominal_inverse;
};

DiscreteLoop MakeDiscreteLoop(const PaperLoop& l) {
  DiscreteLoop d;
  const double ts = l.sample_time;
  d.plant = Discretize(RigidBodyPlant(l.mass, l.damping), ts, Discretization::kZeroOrderHold);
  d.pd = PdFilter(l.kp, l.kd, l.derivative_cutoff_hz, ts);
  // C_FF = P_n⁻¹ on the sampled reference by backward differences: M_n (1 − z⁻¹)²/Ts² + B_n (1 − z⁻¹)/Ts (FIR).
  const double m = l.nominal_mass / (ts * ts), b = l.nominal_damping / ts;
  d.feedforward.b = Eigen::Vector3d(m + b, -2.0 * m - b, m);
  d.feedforward.a = Eigen::Vector3d(1.0, 0.0, 0.0);
  d.feedforward.sample_time = ts;
  d.q = Discretize(BinomialLowPass(l.q_cutoff_hz, l.relative_degree), ts, Discretization::kZeroOrderHold);
  d.q_nominal_inverse =
      Discretize(QNominalInverse(l.q_cutoff_hz, l.relative_degree, l.nominal_mass, l.nominal_damping), ts,
                 l.q_nominal_inverse_discretization);
  return d;
}

// One filter with its state, for the loop simulation.
struct Running {
  const DiscreteTf* tf;
  Eigen::VectorXd state;
  explicit Running(const DiscreteTf& f) : tf(&f), state(Eigen::VectorXd::Zero(std::max(f.order(), 1))) {}
  double Out(double u) const { return FilterOutput(*tf, u, state.data()); }
  void Update(double u) { FilterUpdate(*tf, u, state.data()); }
};

bool Decayed(const Eigen::VectorXd& h) {
  // Stable if the last tenth carries a negligible share of the l1 norm and is not growing.
  const Eigen::Index n = h.size(), tail = std::max<Eigen::Index>(n / 10, 1);
  const double total = h.cwiseAbs().sum();
  if (!std::isfinite(total)) return false;
  return h.tail(tail).cwiseAbs().sum() <= 1e-9 * std::max(total, 1e-300);
}

Complex Jw(double f_hz) { return Complex(0.0, 2.0 * std::numbers::pi * f_hz); }

double Nyquist(double ts) { return 0.5 / ts; }

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// An α bound as JSON: clipped at 0 (no α > 0 certified), null for +∞.
nlohmann::json Bound(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : Number(std::max(v, 0.0)); }

nlohmann::json TermsJson(const SmallGainTerms& t) {
  return {{"gamma_d_to_x", Number(t.gamma_d_to_x)},   {"gamma_xd_to_x", Number(t.gamma_xd_to_x)},
          {"gamma_q", Number(t.gamma_q)},             {"gamma_q_filter", Number(t.gamma_q_filter)},
          {"gamma_x_to_u", Number(t.gamma_x_to_u)},   {"gamma_xdot", Number(t.gamma_xdot)},
          {"gamma_g", Number(t.gamma_g)},             {"lipschitz_x", Number(t.lipschitz_x)},
          {"lipschitz_xdot", Number(t.lipschitz_xdot)}, {"K", Number(LipschitzGain(t))},
          {"alpha_used", Number(t.alpha_max)}};
}

nlohmann::json ComplexJson(Complex c) {
  return {{"magnitude", std::abs(c)}, {"phase_deg", std::arg(c) * 180.0 / std::numbers::pi}};
}

}  // namespace

double LipschitzGain(const SmallGainTerms& t) { return t.lipschitz_x + t.lipschitz_xdot * t.gamma_xdot; }

double RhoPaper(const SmallGainTerms& t) {
  return t.gamma_d_to_x * (t.gamma_q * (1.0 + t.gamma_x_to_u) + t.gamma_g * t.alpha_max * LipschitzGain(t));
}

double RhoConsistent(const SmallGainTerms& t) {
  return t.gamma_d_to_x *
         (t.gamma_q + t.gamma_q_filter * t.gamma_x_to_u + t.gamma_g * t.alpha_max * LipschitzGain(t));
}

double AlphaMaxBoundPaper(const SmallGainTerms& t) {
  const double numerator = 1.0 / t.gamma_d_to_x - t.gamma_q * (1.0 + t.gamma_x_to_u);
  const double denominator = t.gamma_g * LipschitzGain(t);
  if (denominator == 0.0) return numerator > 0.0 ? kInf : -kInf;
  return numerator / denominator;
}

double AlphaMaxBoundDob(const SmallGainTerms& t) {
  const double denominator = t.gamma_d_to_x * t.gamma_g * LipschitzGain(t);
  return denominator == 0.0 ? kInf : 1.0 / denominator;
}

std::string AlphaBoundText(double bound, bool has_gpr) {
  if (std::isnan(bound)) return "α_max unknown";
  if (!(bound > 0.0)) return "no α > 0 is certified: ρ ≥ 1 already at α = 0";
  if (std::isinf(bound)) return has_gpr ? "any α is certified (K = 0)" : "α not bounded without a GPR model (K unknown)";
  return fmt::format("α_max < {:.4g}", bound);
}

const char* ToString(StabilityCondition condition) {
  switch (condition) {
    case StabilityCondition::kNone: return "";
    case StabilityCondition::kLoopStable: return "loop_stable";
    case StabilityCondition::kAdaptiveMassLoopStable: return "adaptive_mass_loop_stable";
    case StabilityCondition::kGprModelGiven: return "gpr_model_given";
    case StabilityCondition::kSmallGain: return "small_gain";
  }
  return "";
}

Eigen::VectorXd LoopImpulseResponse(const PaperLoop& loop, LoopPath path, bool with_dob, int count) {
  if (count < 1) throw std::invalid_argument("LoopImpulseResponse: count must be ≥ 1");
  const DiscreteLoop d = MakeDiscreteLoop(loop);
  Running plant(d.plant), pd(d.pd), ff(d.feedforward), q(d.q), qp(d.q_nominal_inverse);
  const bool dob = with_dob && loop.has_dob;
  Eigen::VectorXd h(count);
  for (int k = 0; k < count; ++k) {
    const double impulse = k == 0 ? 1.0 : 0.0;
    const double dist = path == LoopPath::kDisturbanceToPosition ? impulse : 0.0;
    const double xd = path == LoopPath::kReferenceToPosition ? impulse : 0.0;
    const double x = plant.Out(0.0);  // the ZOH plant is strictly proper
    const double e = xd - x;
    const double dhat = dob ? qp.Out(x) - q.Out(0.0) : 0.0;  // Q is strictly proper
    const double uc = (loop.has_feedforward ? ff.Out(xd) : 0.0) + pd.Out(e) - dhat;
    h(k) = x;
    plant.Update(uc + dist);
    pd.Update(e);
    ff.Update(xd);
    if (dob) {
      qp.Update(x);
      q.Update(uc);
    }
  }
  return h;
}

std::vector<double> LogFrequencies(double min_hz, double sample_time, int count) {
  const double max_hz = 0.99 * Nyquist(sample_time);
  if (!(min_hz > 0.0) || !(min_hz < max_hz) || count < 2) {
    throw std::invalid_argument(fmt::format("LogFrequencies: need 0 < min_hz < 0.99·Nyquist = {} Hz and count ≥ 2",
                                            max_hz));
  }
  std::vector<double> f(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    f[static_cast<std::size_t>(i)] =
        min_hz * std::pow(max_hz / min_hz, static_cast<double>(i) / static_cast<double>(count - 1));
  }
  return f;
}

std::vector<BodePoint> ClosedLoopBode(const PaperLoop& l, const std::vector<double>& frequencies_hz) {
  const DiscreteLoop d = MakeDiscreteLoop(l);
  const ContinuousTf p = RigidBodyPlant(l.mass, l.damping);
  const ContinuousTf pn = RigidBodyPlant(l.nominal_mass, l.nominal_damping);
  const ContinuousTf q = BinomialLowPass(l.q_cutoff_hz, l.relative_degree);
  const ContinuousTf c = PdFilterContinuous(l.kp, l.kd, l.derivative_cutoff_hz);
  std::vector<BodePoint> out;
  for (double f : frequencies_hz) {
    if (!(f > 0.0) || !(f < Nyquist(l.sample_time))) {
      throw std::invalid_argument(fmt::format("ClosedLoopBode: {} Hz is outside (0, Nyquist = {} Hz)", f,
                                              Nyquist(l.sample_time)));
    }
    BodePoint b;
    b.frequency_hz = f;
    const Complex s = Jw(f);
    const double w = 2.0 * std::numbers::pi * f;
    // Without a DOB, Q = Q∘P_n⁻¹ = 0; without the feedforward, C_FF = 0.
    const double dob = l.has_dob ? 1.0 : 0.0, ff = l.has_feedforward ? 1.0 : 0.0;
    {  // Eq. 6, 7 (with P), 12.
      const Complex P = p.Evaluate(s), Pn_inv = 1.0 / pn.Evaluate(s), Q = dob * q.Evaluate(s), C = c.Evaluate(s);
      const Complex den = 1.0 - Q + (C + Q * Pn_inv) * P;
      b.xd_to_x_continuous = (C + ff * Pn_inv) * P / den;
      b.d_to_x_continuous = (1.0 - Q) * P / den;
      b.d_to_dhat_continuous = Q * P * (C + Pn_inv) / den;
    }
    {  // The sampled loop: Q∘P_n⁻¹ is one filter, so eq. 12 becomes Q + (QP_n⁻¹·P − Q)(1 − Q)/Δ.
      const Complex P = d.plant.FrequencyResponse(w), Q = dob * d.q.FrequencyResponse(w);
      const Complex QPn = dob * d.q_nominal_inverse.FrequencyResponse(w), C = d.pd.FrequencyResponse(w);
      // The feedforward is held over each period but sampled mid-interval (time_advance = Ts/2 in the diagrams).
      const Complex Pn_inv = ff / pn.Evaluate(s) * std::exp(Complex(0.0, w * l.sample_time / 2.0));
      const Complex den = 1.0 - Q + (C + QPn) * P;
      b.xd_to_x_discrete = (C + Pn_inv) * P / den;
      b.d_to_x_discrete = (1.0 - Q) * P / den;
      b.d_to_dhat_discrete = Q + (QPn * P - Q) * (1.0 - Q) / den;
    }
    out.push_back(b);
  }
  return out;
}

namespace {

// The "dob" decomposition with the adaptive mass frozen at each end of its clamp (StabilityReport's fields).
void AnalyseAdaptiveMass(const PaperLoop& loop, int n, StabilityReport* r) {
  const double ends[2] = {loop.adaptive_mass_min, loop.adaptive_mass_max};
  std::string verdicts;
  for (int k = 0; k < 2; ++k) {
    const double scale = loop.nominal_mass / (loop.nominal_mass + ends[k]);
    PaperLoop scaled = loop;
    scaled.mass *= scale;
    scaled.damping *= scale;
    const bool finite = std::isfinite(scale) && scale > 0.0;
    const Eigen::VectorXd h_d =
        finite ? LoopImpulseResponse(scaled, LoopPath::kDisturbanceToPosition, true, n) : Eigen::VectorXd();
    const Eigen::VectorXd h_r =
        finite ? LoopImpulseResponse(scaled, LoopPath::kReferenceToPosition, true, n) : Eigen::VectorXd();
    r->adaptive_mass_loop_stable[k] = finite && Decayed(h_d) && Decayed(h_r);
    if (r->adaptive_mass_loop_stable[k]) {
      SmallGainTerms t = r->dob;
      t.gamma_d_to_x = scale * L1Norm(h_d);
      r->adaptive_mass_rho_dob[k] = t.gamma_d_to_x * t.gamma_g * t.alpha_max * LipschitzGain(t);
      r->adaptive_mass_alpha_max_bound_dob[k] = AlphaMaxBoundDob(t);
    }
    verdicts += fmt::format("{}Delta_m_hat = {:g} kg: {}", k ? "; " : "", ends[k],
                            r->adaptive_mass_loop_stable[k]
                                ? fmt::format("stable, rho_dob = {:.4g} ({})", r->adaptive_mass_rho_dob[k],
                                              r->adaptive_mass_rho_dob[k] < 1.0 ? "certified" : "not certified")
                                : std::string("NOT stable"));
  }
  r->notes.push_back(fmt::format(
      "adaptive mass: with the command scaled by (M_n + Delta_m_hat)/M_n and the estimate frozen, the loop is the "
      "designed one on a plant of mass and damping scaled by M_n/(M_n + Delta_m_hat); at the ends of the clamp: {}. "
      "(Fed by the reference acceleration instead, the block is a bounded exogenous input and changes no gamma term.) "
      "The adaptation's own dynamics (a slowly varying gain) are not covered by this analysis",
      verdicts));
}

// The largest certified α in words (StabilityVerdict::alpha_max).
std::string AlphaMaxText(double alpha_max) {
  if (std::isnan(alpha_max)) return "the largest certified α is unknown without a GPR model (--gpr)";
  if (alpha_max <= 0.0) return "no α ≥ 0 is certified";
  if (std::isinf(alpha_max)) return "any α is certified (K = 0)";
  return fmt::format("the largest certified α: α < {:.4g}", alpha_max);
}

// The verdict of the "dob" decomposition: the first condition that fails, or the certificate.
StabilityVerdict Verdict(const StabilityReport& r) {
  StabilityVerdict v;
  v.alpha_used = r.loop.gp_weight;
  const bool adaptive = r.loop.has_adaptive_mass;
  const double ends[2] = {r.loop.adaptive_mass_min, r.loop.adaptive_mass_max};
  if (!r.dob_loop_stable) {
    v.failing_condition = StabilityCondition::kLoopStable;
    v.reason = "the conventional FF/FB/DOB loop (GP path open) is not stable";
    v.alpha_max = 0.0;
  } else if (adaptive && !(r.adaptive_mass_loop_stable[0] && r.adaptive_mass_loop_stable[1])) {
    v.failing_condition = StabilityCondition::kAdaptiveMassLoopStable;
    v.reason = fmt::format("the loop is not stable at Δm̂ = {:g} kg, an end of the adaptive mass's clamp",
                           ends[r.adaptive_mass_loop_stable[0] ? 1 : 0]);
    v.alpha_max = 0.0;
  } else if (!r.has_gpr) {
    if (v.alpha_used > 0.0) {
      v.failing_condition = StabilityCondition::kGprModelGiven;
      v.reason = fmt::format("the GP path (α = {:g}) is not bounded without its GPR model: give --gpr MODEL "
                             "(K = L_x + L_ẋ·γ_ẋ)",
                             v.alpha_used);
    } else {
      v.reason = "the conventional FF/FB/DOB loop is stable and the GP path is off (α = 0)";
    }
  } else {
    double rho = r.rho_dob;
    std::string where;
    v.alpha_max = r.alpha_max_bound_dob;
    for (int k = 0; adaptive && k < 2; ++k) {
      if (r.adaptive_mass_rho_dob[k] > rho) {
        rho = r.adaptive_mass_rho_dob[k];
        where = fmt::format("; at Δm̂ = {:g} kg, an end of the adaptive mass's clamp", ends[k]);
      }
      v.alpha_max = std::min(v.alpha_max, r.adaptive_mass_alpha_max_bound_dob[k]);
    }
    const bool small = rho < 1.0;
    if (!small) v.failing_condition = StabilityCondition::kSmallGain;
    v.reason = fmt::format("ρ = {:.4g} {} 1 at α = {:g} (small gain, DOB loop closed{})", rho, small ? "<" : "≥",
                           v.alpha_used, where);
  }
  v.certified = v.failing_condition == StabilityCondition::kNone;
  v.line = fmt::format("{}: {}; {}", v.certified ? "certified" : "NOT certified", v.reason, AlphaMaxText(v.alpha_max));
  return v;
}

}  // namespace

StabilityReport AnalyseStability(const PaperLoop& loop, const GprModel* gpr, const StabilityOptions& options) {
  StabilityReport r;
  r.loop = loop;
  const DiscreteLoop d = MakeDiscreteLoop(loop);
  const int n = options.impulse_samples;

  // Per-filter gains (Assumption 2, 5).
  SmallGainTerms base;
  base.gamma_q = loop.has_dob ? L1Norm(d.q_nominal_inverse) : 0.0;
  base.gamma_q_filter = loop.has_dob ? L1Norm(d.q) : 0.0;
  base.gamma_xdot = L1Norm(VelocityEstimatorFilter(loop.velocity_cutoff_hz, loop.sample_time));
  base.gamma_g =
      L1Norm(Discretize(BinomialLowPass(loop.gp_cutoff_hz, loop.gp_order), loop.sample_time,
                        Discretization::kZeroOrderHold));
  base.alpha_max = loop.gp_weight;
  if (gpr) {
    const GprLipschitzConstants lc = loop.gp_confidence_weighting
                                         ? gpr->ConfidenceWeightedLipschitzConstants(options.weighted_lipschitz_grid)
                                         : gpr->LipschitzConstants(options.lipschitz_grid);
    base.lipschitz_x = lc.position;
    base.lipschitz_xdot = lc.velocity;
    r.b_mu = gpr->PosteriorErrorBound(options.beta_delta, options.std_grid);
    r.has_gpr = true;
  }

  // "paper" decomposition: inner loop P + C_FB.
  const Eigen::VectorXd h_inner_d = LoopImpulseResponse(loop, LoopPath::kDisturbanceToPosition, false, n);
  const Eigen::VectorXd h_inner_r = LoopImpulseResponse(loop, LoopPath::kReferenceToPosition, false, n);
  r.inner_loop_stable = Decayed(h_inner_d) && Decayed(h_inner_r);
  r.paper = base;
  r.paper.gamma_d_to_x = r.inner_loop_stable ? L1Norm(h_inner_d) : kInf;
  r.paper.gamma_xd_to_x = r.inner_loop_stable ? L1Norm(h_inner_r) : kInf;
  r.paper.gamma_x_to_u = L1Norm(d.pd);

  // "dob" decomposition: the conventional loop closed.
  const Eigen::VectorXd h_dob_d = LoopImpulseResponse(loop, LoopPath::kDisturbanceToPosition, true, n);
  const Eigen::VectorXd h_dob_r = LoopImpulseResponse(loop, LoopPath::kReferenceToPosition, true, n);
  r.dob_loop_stable = Decayed(h_dob_d) && Decayed(h_dob_r);
  r.dob = base;
  r.dob.gamma_d_to_x = r.dob_loop_stable ? L1Norm(h_dob_d) : kInf;
  r.dob.gamma_xd_to_x = r.dob_loop_stable ? L1Norm(h_dob_r) : kInf;
  r.dob.gamma_q = 0.0;
  r.dob.gamma_x_to_u = 0.0;

  r.rho_paper = RhoPaper(r.paper);
  r.rho_consistent = RhoConsistent(r.paper);
  r.alpha_max_bound_paper = AlphaMaxBoundPaper(r.paper);
  r.rho_dob = r.dob.gamma_d_to_x * r.dob.gamma_g * r.dob.alpha_max * LipschitzGain(r.dob);
  r.alpha_max_bound_dob = AlphaMaxBoundDob(r.dob);

  r.bode = ClosedLoopBode(loop, LogFrequencies(options.bode_min_hz, loop.sample_time, options.bode_points));

  if (!r.inner_loop_stable) r.notes.push_back("the inner loop P + C_FB is not stable (Assumption 1 fails)");
  if (!r.dob_loop_stable) r.notes.push_back("the conventional FF/FB/DOB loop is not stable");
  if (!loop.has_dob) {
    r.notes.push_back("the loop has no DOB: the 'dob' decomposition closes the PD loop alone (gamma_q = 0)");
  }
  r.notes.push_back(fmt::format("eq. 58 as printed: rho = {:.4g} ({}); per-path Lemma 1: rho' = {:.4g}", r.rho_paper,
                                r.rho_paper < 1.0 ? "< 1, BIBO stable" : ">= 1, not certified", r.rho_consistent));
  if (r.rho_paper >= 1.0) {
    r.notes.push_back("the 'paper' decomposition bounds d_hat_d through gamma_x_to_u = ||C_FB||_1, and "
                      "gamma_d_to_x * ||C_FB||_1 >= ||T||_1 >= 1, so it cannot certify a PD loop; use the 'dob' "
                      "decomposition (conventional loop closed, only the GP path fed back)");
  }
  if (r.has_gpr && loop.gp_confidence_weighting) {
    r.notes.push_back("the gpr block scales its mean by the confidence weight g(x, xdot): L_x and L_xdot are those of "
                      "g * mean, largest difference quotients on a grid (a sampled estimate, not a rigorous bound)");
  }
  if (loop.has_adaptive_mass) AnalyseAdaptiveMass(loop, n, &r);
  if (!r.has_gpr) {
    r.notes.push_back("no GPR model given: K = L_x + L_xdot*gamma_xdot = 0, the GP path is absent");
  }
  r.notes.push_back(fmt::format("'dob' decomposition: rho = {:.4g}; {}", r.rho_dob,
                                AlphaBoundText(r.alpha_max_bound_dob, r.has_gpr)));
  r.verdict = Verdict(r);
  return r;
}

nlohmann::json ToJson(const StabilityReport& r) {
  const PaperLoop& l = r.loop;
  nlohmann::json j;
  j["loop"] = {{"sample_time", l.sample_time},
               {"mass", l.mass},
               {"damping", l.damping},
               {"nominal_mass", l.nominal_mass},
               {"nominal_damping", l.nominal_damping},
               {"q_cutoff_hz", l.q_cutoff_hz},
               {"relative_degree", l.relative_degree},
               {"q_nominal_inverse_discretization", ToString(l.q_nominal_inverse_discretization)},
               {"kp", l.kp},
               {"kd", l.kd},
               {"derivative_cutoff_hz", l.derivative_cutoff_hz},
               {"velocity_cutoff_hz", l.velocity_cutoff_hz},
               {"gp_weight", l.gp_weight},
               {"gp_cutoff_hz", l.gp_cutoff_hz},
               {"gp_order", l.gp_order},
               {"gp_confidence_weighting", l.gp_confidence_weighting},
               {"has_dob", l.has_dob},
               {"has_feedforward", l.has_feedforward},
               {"has_adaptive_mass", l.has_adaptive_mass},
               {"adaptive_mass_min_kg", l.adaptive_mass_min},
               {"adaptive_mass_max_kg", l.adaptive_mass_max}};
  if (l.has_adaptive_mass) {
    j["adaptive_mass"] = {{"loop_stable_at_min_max", {r.adaptive_mass_loop_stable[0], r.adaptive_mass_loop_stable[1]}},
                          {"rho_dob_at_min_max", {Number(r.adaptive_mass_rho_dob[0]), Number(r.adaptive_mass_rho_dob[1])}},
                          {"alpha_max_bound_dob_at_min_max",
                           {Bound(r.adaptive_mass_alpha_max_bound_dob[0]), Bound(r.adaptive_mass_alpha_max_bound_dob[1])}}};
  }
  j["inner_loop_stable"] = r.inner_loop_stable;
  j["dob_loop_stable"] = r.dob_loop_stable;
  j["has_gpr"] = r.has_gpr;
  j["b_mu"] = r.b_mu;
  j["paper"] = TermsJson(r.paper);
  j["paper"]["rho"] = Number(r.rho_paper);
  j["paper"]["rho_consistent"] = Number(r.rho_consistent);
  j["paper"]["alpha_max_bound"] = Bound(r.alpha_max_bound_paper);
  j["dob"] = TermsJson(r.dob);
  j["dob"]["rho"] = Number(r.rho_dob);
  j["dob"]["alpha_max_bound"] = Bound(r.alpha_max_bound_dob);
  const StabilityVerdict& v = r.verdict;
  j["verdict"] = {{"certified", v.certified},
                  {"decomposition", "dob"},
                  {"failing_condition",
                   v.certified ? nlohmann::json(nullptr) : nlohmann::json(ToString(v.failing_condition))},
                  {"reason", v.reason},
                  {"alpha_used", v.alpha_used},
                  {"alpha_max", Number(v.alpha_max)},
                  {"alpha_max_text", AlphaMaxText(v.alpha_max)},
                  {"line", v.line}};
  nlohmann::json bode = nlohmann::json::array();
  for (const BodePoint& b : r.bode) {
    bode.push_back({{"frequency_hz", b.frequency_hz},
                    {"eq6_continuous", ComplexJson(b.xd_to_x_continuous)},
                    {"eq7_continuous", ComplexJson(b.d_to_x_continuous)},
                    {"eq12_continuous", ComplexJson(b.d_to_dhat_continuous)},
                    {"eq6_discrete", ComplexJson(b.xd_to_x_discrete)},
                    {"eq7_discrete", ComplexJson(b.d_to_x_discrete)},
                    {"eq12_discrete", ComplexJson(b.d_to_dhat_discrete)}});
  }
  j["bode"] = std::move(bode);
  j["notes"] = r.notes;
  j["null_means"] = "infinite (unbounded gain or no bound)";
  return j;
}

}  // namespace mb
