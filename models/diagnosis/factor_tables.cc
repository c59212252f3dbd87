// The diagnosis grammar's two tables (factors.h; issue 45; DIAGNOSIS.md, "Generated, not listed"): what a missing
// force is proportional to (the multipliers) and what it varies with (the modulators). effects/factor_products.cc
// crosses them; every pair is a candidate, named and worded from its rows, unless a hand-written effect of the
// catalogue holds it (EffectRegistry::Add). Sources: Brunton, Proctor & Kutz 2016 (SINDy's library of products);
// Duvenaud et al. 2013 (the Automatic Statistician's grammar of kernels); Goldstein, Classical Mechanics, §1.4
// (a mass that varies with the position); Chow 1960 and Andrews 1993 (a break at an unknown time).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/parameter_text.h"
#include "models/diagnosis/periodogram.h"
#include "models/diagnosis/signal_processing.h"
#include "models/diagnosis/time_chirp.h"

namespace mb {
namespace {

constexpr double kMinBumpShare = 0.005;     // of the residual's sum of squares: a bump that removes less is noise
constexpr int kSmoothDegree = 3;            // ξ, ξ², ξ³: position_dependent_force's default
constexpr double kTimeTrim = 0.1;           // of the record's duration left out at each end of a break scan (Andrews)
constexpr int kBreakGrid = 81;              // break times scanned (then RefineTime around the best)
constexpr int kWindowGrid = 25;             // window edges scanned (then each edge by RefineTime)

double Need(const FactorParameters& p, const char* key, const std::string& name) {
  const auto it = p.find(key);
  if (it == p.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(
        fmt::format("effect '{}': parameter '{}' is missing or not finite; set it (SI units)", name, key));
  }
  return it->second;
}

double NeedPositive(const FactorParameters& p, const char* key, const std::string& name) {
  const double value = Need(p, key, name);
  if (!(value > 0.0)) {
    throw std::invalid_argument(fmt::format("effect '{}': parameter '{}' = {} must be positive", name, key, value));
  }
  return value;
}

EffectRegressors Scaled(const std::string& name, Eigen::VectorXd column, const Eigen::VectorXd* scale) {
  if (scale != nullptr) column.array() *= scale->array();
  return SingleColumn(name, std::move(column));
}

// A parameter for words: NaN when absent.
double Value(const FactorParameters& p, const char* key) {
  const auto it = p.find(key);
  return it == p.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}

const Eigen::VectorXd& ModelForce(const DiagnosisSignals& s, const std::string& effect) {
  if (s.drive_force.size() > 0) return s.drive_force;
  const auto own = s.command_with.find(effect);
  return own != s.command_with.end() ? own->second : NeedModelOutput({effect, {}}, s);
}

// ---- The multipliers ----

std::vector<MultiplierRow> MakeMultipliers() {
  std::vector<MultiplierRow> rows;
  rows.push_back({"one", "force", "a force", "1",
                  "a force of what the modulator varies with alone (a spring, a cable carrier, a coupling)", "",
                  false, false, false, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string&) {
                    return Eigen::VectorXd::Ones(s.size()).eval();
                  },
                  One(), false});
  rows.push_back({"slip", "coulomb", "the Coulomb friction level", "tanh(v/v_s)",
                  "a friction: preload, magnetic attraction, a seal, the lubrication, the guide's straightness", "",
                  true, false, true, false,
                  [](const DiagnosisSignals&, const Eigen::VectorXd& slip, const std::string&) { return slip; },
                  SlipOfVelocity(), false});
  rows.push_back({"velocity", "damping", "the viscous friction", "v",
                  "a damping: the lubricant's viscosity, eddy currents, the back-EMF", "/(m/s)", false, false, true,
                  false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string&) { return s.velocity; },
                  MeasuredMotion(MotionInput::kVelocity), false});
  rows.push_back({"speed", "speed_force", "a force growing with the speed", "|v|",
                  "a force of the speed in either direction (the magnetic drag of a passing slot, a fan's load)",
                  "/(m/s)", false, false, false, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string&) {
                    return s.velocity.cwiseAbs().eval();
                  },
                  AbsOf(MeasuredMotion(MotionInput::kVelocity)), true});
  rows.push_back({"velocity_speed", "drag", "the quadratic drag", "v·|v|",
                  "a drag of a fluid at high Reynolds number (an orifice, air, a seal's pumping)", "/(m/s)²", false,
                  false, true, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string&) {
                    return s.velocity.cwiseProduct(s.velocity.cwiseAbs()).eval();
                  },
                  Times(MeasuredMotion(MotionInput::kVelocity), AbsOf(MeasuredMotion(MotionInput::kVelocity))), true});
  rows.push_back({"acceleration", "inertia", "the moving mass", "a (with a factor M(x) of the position: M(x)·a + ½M′(x)·v²)",
                  "a mass: a payload, a tool, a linkage or an arm whose reflected inertia changes", "/(m/s²)", false,
                  false, false, true,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string&) { return s.acceleration; },
                  MeasuredMotion(MotionInput::kAcceleration), false});
  rows.push_back({"model_force", "force_constant", "the force constant", "ŷ (the model's force from the measured motion)",
                  "the motor's force constant: the magnets' flux, the air gap, the coil's temperature", "", false,
                  true, false, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string& effect) {
                    return ModelForce(s, effect);
                  },
                  mb::ModelForce(), false});
  rows.push_back({"model_force_abs", "force_constant_saturation", "the force constant at high force", "ŷ·|ŷ|",
                  "the iron saturating at high current: the force constant falls with the force", "/N", false, true,
                  false, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd&, const std::string& effect) {
                    const Eigen::VectorXd& y = ModelForce(s, effect);
                    return y.cwiseProduct(y.cwiseAbs()).eval();
                  },
                  Times(mb::ModelForce(), AbsOf(mb::ModelForce())), true});
  rows.push_back({"load_slip", "load_friction", "the friction growing with the transmitted force", "|ŷ|·tanh(v/v_s)",
                  "a load-dependent friction: a screw's or a gear's flanks, a preloaded guide under the drive's force",
                  "/N", true, true, true, false,
                  [](const DiagnosisSignals& s, const Eigen::VectorXd& slip, const std::string& effect) {
                    return ModelForce(s, effect).cwiseAbs().cwiseProduct(slip).eval();
                  },
                  // |ŷ|·tanh(v/v_s) as ŷ × sign(ŷ)·tanh(v/v_s): a share of the drive's force, as the force constant's.
                  Times(mb::ModelForce(), Times(SignOf(mb::ModelForce()), SlipOfVelocity())), true});
  return rows;
}

// ---- The modulators' shape scans ----

std::vector<FactorParameters> ScanNothing(ProposalContext&,
                                          const Eigen::VectorXd&, const Eigen::VectorXd*, const std::string&) {
  return {FactorParameters{}};
}

std::vector<FactorParameters> ScanPositionPeriod(ProposalContext& c,
                                                 const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string&) {
  std::vector<ProposedPeriod> periods = c.position_periods();
  // The period of the residual demodulated by the multiplier first: a friction along the pitch reverses with the
  // direction of travel and cancels in the plain periodogram.
  if ((m.array() != 1.0).any()) {
    if (const std::optional<ProposedPeriod> own = ModulatedPeriod(c, m)) periods.insert(periods.begin(), *own);
  }
  std::vector<FactorParameters> out;
  std::vector<double> proposed;
  for (const ProposedPeriod& period : periods) {
    if (std::any_of(proposed.begin(), proposed.end(), [&](double q) { return std::abs(q - period.period) < 1e-3 * q; })) {
      continue;
    }
    proposed.push_back(period.period);
    out.push_back({{"period", period.period}, {"harmonics", period.harmonics}});
  }
  return out;
}

std::vector<FactorParameters> ScanPositionBump(ProposalContext& c, const Eigen::VectorXd& m,
                                               const Eigen::VectorXd* kinetic, const std::string&) {
  const BumpPlace place = ScanBump(c, m, kinetic);
  if (!(place.explained >= kMinBumpShare)) return {};
  return {{{"center", place.center}, {"half_width", place.half_width}}};
}

std::vector<FactorParameters> ScanPositionSmooth(ProposalContext& c,
                                                 const Eigen::VectorXd&, const Eigen::VectorXd*, const std::string&) {
  const Eigen::VectorXd& x = c.signals().position;
  if (!(c.position_span() > 0.0)) return {};
  if (const auto ripple = RippleASmoothFunctionWouldBlur(c)) {
    c.Note(fmt::format("smooth functions of the position not proposed yet: a ripple of {:.3g} cycles in the travel "
                       "holds {:.1f} % of the residual, which they would only blur (proposed once the ripple is in the "
                       "model)",
                       c.position_span() / ripple->period, 100.0 * ripple->power));
    return {};
  }
  return {{{"center", 0.5 * (x.maxCoeff() + x.minCoeff())}, {"half_range", 0.5 * c.position_span()}}};
}

std::vector<FactorParameters> ScanColumns(ProposalContext& c,
                                          const Eigen::VectorXd&, const Eigen::VectorXd*, const std::string&) {
  const DiagnosisSignals& s = c.signals();
  std::vector<FactorParameters> out;
  for (std::size_t k = 0; k < s.extra_columns.size(); ++k) {
    // A column that varies and is a new signal (logged_column notes the others).
    if (!(s.extra_columns[k].maxCoeff() > s.extra_columns[k].minCoeff()) || UnreadColumnDuplicate(s, k)) continue;
    out.push_back({{"column", static_cast<double>(k)}});
  }
  return out;
}

// The record's first instant and duration [s].
std::pair<double, double> Span(const DiagnosisSignals& s) { return {s.time(0), s.time(s.size() - 1) - s.time(0)}; }

std::vector<FactorParameters> ScanRamp(ProposalContext& c,
                                       const Eigen::VectorXd&, const Eigen::VectorXd*, const std::string&) {
  const auto [t0, duration] = Span(c.signals());
  if (!(duration > 0.0)) return {};
  return {{{"start_time", t0}, {"end_time", t0 + duration}}};
}

// The minimum of f over [a, b], to `resolution`: a grid of kRefineGrid points over the bracket, then golden section
// between the best point's neighbours; `fallback` with its value when neither ends lower. Golden section alone assumes
// f unimodal, and a time scan's error is not: it is flat over a dwell, where the motion and with it the column are zero,
// so both probes tie there and the search keeps the wrong side (grammar seed 20: a mass window's end drawn into the
// dwell before the move it ends in, 7.13 s for 7.57 s).
std::pair<double, double> RefineTime(const std::function<double(double)>& f, double a, double b, double resolution,
                                     double fallback, double fallback_value) {
  constexpr int kRefineGrid = 33;
  const double h = (b - a) / (kRefineGrid - 1);
  double x = fallback, e = fallback_value;
  for (int i = 0; i < kRefineGrid; ++i) {
    const double xi = a + i * h, ei = f(xi);
    if (ei < e) { x = xi; e = ei; }
  }
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = std::max(a, x - h), hi = std::min(b, x + h);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), e1 = f(x1), e2 = f(x2);
  for (int it = 0; it < 30 && hi - lo > resolution; ++it) {
    if (e1 < e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = f(x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = f(x2);
    }
  }
  const double xm = 0.5 * (lo + hi), em = f(xm);
  return em <= e ? std::pair{xm, em} : std::pair{x, e};
}

// The joint fit of a time scan (a step's time, a window's edges, a settling time) without the samples at the record's
// two ends where the derived motion is still its derivative filter's edge transient (ProposalContext::edge_samples):
// a sweep's first kick of the controller there, a hundred times the noise, drew the time scans to the record's ends
// (grammar seeds 201, 261).
class TimeScanFit {
 public:
  explicit TimeScanFit(const ProposalContext& c)
      : edge_(c.edge_samples()), base_(Trimmed(c.BaseWithConstant())), r_(Trimmed(c.residual())),
        fit_(base_, r_, c.loop()) {}
  TimeScanFit(const TimeScanFit&) = delete;
  TimeScanFit& operator=(const TimeScanFit&) = delete;
  // The residual sum of squares of the trimmed residual on [base, 1, column] (column: N).
  double operator()(Eigen::VectorXd column) const { return fit_(Trimmed(std::move(column))); }

 private:
  template <typename M>
  M Trimmed(M x) const {
    const Eigen::Index rows = x.rows();
    return WithoutEdges(std::move(x), edge_, rows);
  }
  Eigen::Index edge_;
  Eigen::MatrixXd base_;
  Eigen::VectorXd r_;
  JointFitResidual fit_;
};

Eigen::VectorXd StepColumn(const DiagnosisSignals& s, const Eigen::VectorXd& m, double change_time) {
  return (s.time.array() >= change_time).select(m, 0.0);
}

Eigen::VectorXd WindowColumn(const DiagnosisSignals& s, const Eigen::VectorXd& m, double on, double off) {
  return (s.time.array() >= on && s.time.array() < off).select(m, 0.0);
}

// A break at an unknown time: the joint fit of the residual on [base, 1, m·H(t − t_c)] over a grid of t_c in the
// middle 80 % of the record, then RefineTime between the best point's neighbours (Andrews' sup-F scan, the Chow test
// at an unknown time). None when the best break is at the scan's edge (no change inside the record).
std::vector<FactorParameters> ScanStep(ProposalContext& c,
                                       const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string& pair) {
  const DiagnosisSignals& s = c.signals();
  if (!(Span(s).second > 0.0) || !(m.cwiseAbs().maxCoeff() > 0.0)) return {};
  const TimeScanFit fit(c);
  const auto sse = [&](double t) { return fit(StepColumn(s, m, t)); };
  const auto [lo, hi] = TimeScanRange("change_time", s.time);
  const double step = (hi - lo) / (kBreakGrid - 1);
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kBreakGrid; ++i) {
    const double e = sse(lo + i * step);
    if (e < best_sse) { best_sse = e; best = i; }
  }
  if (best == 0 || best == kBreakGrid - 1) {
    c.Note(fmt::format("{} not proposed: its best change time ({:.4g} s) is at the scan's {} ({:.4g}–{:.4g} s): no "
                       "change inside the record", pair, lo + best * step, best == 0 ? "start" : "end", lo,
                       lo + (kBreakGrid - 1) * step));
    return {};
  }
  const double at = RefineTime(sse, lo + (best - 1) * step, lo + (best + 1) * step, 0.1 * c.sample_period(),
                           lo + best * step, best_sse).first;
  return {{{"change_time", at}}};
}

// On between two times: the joint fit of the residual on [base, 1, m·1(t_on ≤ t < t_off)] over a grid of both edges
// in the middle 90 % of the record, then each edge by RefineTime between its neighbours. None when the best window
// touches the scan's ends (a step, or a ramp, fits that).
std::vector<FactorParameters> ScanWindow(ProposalContext& c,
                                         const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string& pair) {
  const DiagnosisSignals& s = c.signals();
  if (!(Span(s).second > 0.0) || !(m.cwiseAbs().maxCoeff() > 0.0)) return {};
  const TimeScanFit fit(c);
  const auto [lo, hi] = TimeScanRange("on_time", s.time);
  const double step = (hi - lo) / (kWindowGrid - 1);
  int best_on = 0, best_off = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kWindowGrid; ++i) {
    for (int j = i + 2; j < kWindowGrid; ++j) {
      const double e = fit(WindowColumn(s, m, lo + i * step, lo + j * step));
      if (e < best_sse) { best_sse = e; best_on = i; best_off = j; }
    }
  }
  if (best_on == 0 || best_off == kWindowGrid - 1) {
    c.Note(fmt::format("{} not proposed: its best window ({:.4g}–{:.4g} s) touches the scan's {} (a step or a ramp "
                       "fits that)", pair, lo + best_on * step, lo + best_off * step, best_on == 0 ? "start" : "end"));
    return {};
  }
  double on = lo + best_on * step, off = lo + best_off * step;
  const double resolution = 0.1 * c.sample_period();
  std::tie(on, best_sse) = RefineTime([&](double t) { return fit(WindowColumn(s, m, t, off)); }, on - step, on + step,
                                  resolution, on, best_sse);
  std::tie(off, best_sse) = RefineTime([&](double t) { return fit(WindowColumn(s, m, on, t)); }, off - step, off + step,
                                   resolution, off, best_sse);
  return {{{"on_time", on}, {"off_time", off}}};
}

Eigen::VectorXd WarmUp(const Eigen::VectorXd& t, double start, double time_constant) {
  return t.unaryExpr([&](double ti) { return ti < start ? 0.0 : -std::expm1(-(ti - start) / time_constant); });
}

// A first-order settling from the record's start: T on a log grid over [duration/100, duration] then golden section
// (MinimiseOnLogGrid); none when T ends in the grid's first or last cell (a step at the start, or a ramp).
std::vector<FactorParameters> ScanWarmUp(ProposalContext& c,
                                         const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string& pair) {
  constexpr int kGrid = 25;
  const DiagnosisSignals& s = c.signals();
  const auto [start, duration] = Span(s);
  const double t0 = start;  // a plain copy: clang 14 does not capture a structured binding in a lambda
  if (!(duration > 0.0) || !(m.cwiseAbs().maxCoeff() > 0.0)) return {};
  const TimeScanFit fit(c);
  const double lo = duration / 100.0, hi = duration;
  const double time_constant = MinimiseOnLogGrid(
      lo, hi, kGrid, 20, [&](double T) { return fit(m.cwiseProduct(WarmUp(s.time, t0, T))); }, true);
  const double cell = std::pow(hi / lo, 1.0 / (kGrid - 1));
  if (!(time_constant > lo * cell && time_constant < hi / cell)) {
    c.Note(fmt::format("{} not proposed: its best settling time ({:.3g} s) is at the scan's {} end ({:.3g}–{:.3g} s): {}",
                       pair, time_constant, time_constant <= lo * cell ? "short" : "long", lo, hi,
                       time_constant <= lo * cell ? "a step at the record's start" : "a drift over the record"));
    return {};
  }
  return {{{"start_time", t0}, {"time_constant", time_constant}}};
}

// A vibration of time: the strongest peak of the residual's time periodogram — of the residual demodulated by the
// multiplier when it is not 1 — that is not locked to the motion's repetition (MotionHarmonic).
std::vector<FactorParameters> ScanTimePeriod(ProposalContext& c,
                                             const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string&) {
  std::optional<Periodogram> demodulated;
  const Periodogram* pg = &c.search().time_periodogram;
  if ((m.array() != 1.0).any()) {
    demodulated = DemodulatedPeriodogram(c, c.signals().time, m, c.options().time_periodogram);
    if (!demodulated) return {};
    pg = &*demodulated;
  }
  for (std::size_t i = 0; i < pg->peaks.size(); ++i) {
    const PeriodogramPeak& peak = pg->peaks[i];
    if (peak.harmonic_of >= 0 || (demodulated && !peak.significant) || MotionHarmonic(c, 1.0 / peak.period) > 0) {
      continue;
    }
    return {{{"frequency_hz", 1.0 / peak.period},
             {"harmonics", HarmonicCount(*pg, i, c.options().max_harmonics)}}};
  }
  return {};
}

// ---- The modulators' shapes ----

EffectRegressors PeriodicShape(const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                               const Eigen::VectorXd* scale) {
  const auto harmonics = p.find("harmonics");
  return PeriodicColumns(s.position, NeedPositive(p, "period", name),
                         harmonics == p.end() ? 1 : std::max(1, static_cast<int>(harmonics->second)), name, scale);
}

Eigen::MatrixXd PeriodicDerivative(const FactorParameters& p, const DiagnosisSignals& s, const Eigen::VectorXd& scale) {
  const double period = NeedPositive(p, "period", "position_periodic");
  const auto h = p.find("harmonics");
  const int harmonics = h == p.end() ? 1 : std::max(1, static_cast<int>(h->second));
  Eigen::MatrixXd out(s.size(), 2 * harmonics);
  for (int k = 1; k <= harmonics; ++k) {
    const double w = 2.0 * std::numbers::pi * k / period;
    const Eigen::ArrayXd theta = w * s.position.array();
    out.col(2 * (k - 1)) = (-w * theta.sin() * scale.array()).matrix();
    out.col(2 * k - 1) = (w * theta.cos() * scale.array()).matrix();
  }
  return out;
}

Eigen::MatrixXd BumpDerivative(const FactorParameters& p, const DiagnosisSignals& s, const Eigen::VectorXd& scale) {
  const double center = Need(p, "center", "position_local"), w = NeedPositive(p, "half_width", "position_local");
  return BumpSlope(s.position, center, w).cwiseProduct(scale);
}

Eigen::MatrixXd SmoothDerivative(const FactorParameters& p, const DiagnosisSignals& s, const Eigen::VectorXd& scale) {
  const double center = Need(p, "center", "position_smooth"), h = NeedPositive(p, "half_range", "position_smooth");
  Eigen::MatrixXd out(s.size(), kSmoothDegree);
  const Eigen::ArrayXd xi = (s.position.array() - center) / h;
  for (int j = 1; j <= kSmoothDegree; ++j) out.col(j - 1) = (j / h * xi.pow(j - 1) * scale.array()).matrix();
  return out;
}

const Eigen::VectorXd& Column(const FactorParameters& p, const DiagnosisSignals& s, const std::string& name) {
  return UnreadColumn({name, p}, s);
}

std::vector<ModulatorRow> MakeModulators() {
  std::vector<ModulatorRow> rows;
  rows.push_back({"constant", "{}", "", "1", "", {}, false, Periodicity::kNone, nullptr,
                  [](const FactorParameters&, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) { return Scaled(name, Eigen::VectorXd::Ones(s.size()), scale); },
                  nullptr, ScanNothing, {}, {}});
  rows.back().words = [](const FactorParameters&, double k, const std::string& u, const std::string&, const std::string&) {
    return fmt::format("is missing: {:+.4g}{}", k, u);
  };
  rows.push_back({"position_periodic", "{}_ripple", "rippling along the travel", "cos(2πkx/P), sin(2πkx/P), k = 1..K",
                  "a pitch of the machine: the magnets, the slots, a screw's lead, a gear's tooth",
                  {{"period", "m", "P: the pitch"}, {"harmonics", "", "K, 1 when absent"}}, true,
                  Periodicity::kPosition, RefinePositionPeriod, PeriodicShape, PeriodicDerivative,
                  ScanPositionPeriod, {}, {}});
  rows.back().words = [](const FactorParameters& p, double, const std::string&, const std::string&, const std::string& unit) {
    return fmt::format("ripples along the travel with period {}", FormatParameterValue(Value(p, "period"), "m", unit));
  };
  rows.push_back({"position_local", "local_{}", "over one stretch of the travel", "cos²(π(x − c)/(2w)) for |x − c| < w",
                  "one place: a damaged spot, debris, a seal, a chipped magnet, a bellows",
                  {{"center", "m", "c: the middle of the stretch where it acts"},
                   {"half_width", "m", "w: it acts over [c − w, c + w]"}},
                  true, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    return Scaled(name, Bump(s.position, Need(p, "center", name), NeedPositive(p, "half_width", name)),
                                  scale);
                  },
                  BumpDerivative, ScanPositionBump, {}, {}});
  rows.back().words = [](const FactorParameters& p, double, const std::string&, const std::string&, const std::string& unit) {
    return fmt::format("changes over the stretch {} ± {}", FormatParameterValue(Value(p, "center"), "m", unit),
                       FormatParameterValue(Value(p, "half_width"), "m", unit));
  };
  rows.push_back({"position_smooth", "{}_along_travel", "changing smoothly along the travel", "ξ^j, ξ = (x − x₀)/h, j = 1..3",
                  "the travel's length: a guide out of straightness, an air gap that opens, a cable carrier",
                  {{"center", "m", "x₀: the middle of the record's travel"},
                   {"half_range", "m", "h: half the record's travel"}},
                  true, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    return PowerColumns(s.position, Need(p, "center", name), NeedPositive(p, "half_range", name),
                                        kSmoothDegree, name, scale);
                  },
                  SmoothDerivative, ScanPositionSmooth, {}, {}});
  rows.back().words = [](const FactorParameters& p, double, const std::string&, const std::string&, const std::string& unit) {
    return fmt::format("changes smoothly along the travel, over {} ± {}", FormatParameterValue(Value(p, "center"), "m", unit),
                       FormatParameterValue(Value(p, "half_range"), "m", unit));
  };
  rows.push_back({"column", "column_{}", "following a log column", "c − c̄, c a log column the diagram does not read",
                  "what the column measures: a temperature, another axis, a load cell, a bus voltage",
                  {{"column", "", "the column's index among the log's unread columns (named in the description)"}},
                  false, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) { return Scaled(name, Centered(Column(p, s, name)), scale); },
                  nullptr, ScanColumns, {}, {}});
  rows.back().words = [](const FactorParameters&, double k, const std::string& u, const std::string& column, const std::string&) {
    return fmt::format("follows '{}': {:+.4g}{} per unit of it", column, k, u);
  };
  rows.push_back({"column_rate", "column_rate_{}", "following a log column's rate", "dc/dt, c a log column",
                  "a coupling through a lag: another axis's velocity or jerk, a flow",
                  {{"column", "", "the column's index among the log's unread columns (named in the description)"}},
                  false, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    return Scaled(name, CentralDifference(s.time, Column(p, s, name)), scale);
                  },
                  nullptr, ScanColumns, {}, {}});
  rows.back().words = [](const FactorParameters&, double k, const std::string& u, const std::string& column, const std::string&) {
    return fmt::format("follows the rate of '{}': {:+.4g}{} per unit of it per second", column, k, u);
  };
  rows.push_back({"time_ramp", "{}_drift", "drifting over the record", "(t − t_s)/(t_e − t_s)",
                  "a slow change: wear, a temperature rising", {{"start_time", "s", "t_s: the record's first instant"},
                                                              {"end_time", "s", "t_e: the record's last instant"}},
                  false, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    const double start = Need(p, "start_time", name), end = Need(p, "end_time", name);
                    if (!(end > start)) throw std::invalid_argument(fmt::format("effect '{}': end_time must lie after start_time", name));
                    return Scaled(name, ((s.time.array() - start) / (end - start)).cwiseMin(1.0).cwiseMax(0.0).matrix(), scale);
                  },
                  nullptr, ScanRamp, {}, {}});
  rows.back().words = [](const FactorParameters&, double k, const std::string& u, const std::string&, const std::string&) {
    return fmt::format("drifts over the record: {:+.4g}{} from its start to its end", k, u);
  };
  rows.push_back({"time_step", "{}_step", "changing at one time", "H(t − t_c)",
                  "a change of the machine: a payload picked up, a tool change, a switch",
                  {{"change_time", "s", "t_c: when it changes"}}, false, Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    return Scaled(name, (s.time.array() >= Need(p, "change_time", name)).cast<double>().matrix(), scale);
                  },
                  nullptr, ScanStep, {}, {}});
  rows.back().words = [](const FactorParameters& p, double k, const std::string& u, const std::string&, const std::string&) {
    return fmt::format("changes at {:.4g} s by {:+.4g}{}", Value(p, "change_time"), k, u);
  };
  rows.push_back({"time_window", "{}_window", "present between two times", "1 for t_on ≤ t < t_off",
                  "something on for a while: a payload carried and set down, a clamp, a second axis running",
                  {{"on_time", "s", "t_on: when it comes"}, {"off_time", "s", "t_off: when it goes"}}, false,
                  Periodicity::kNone, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    const double on = Need(p, "on_time", name), off = Need(p, "off_time", name);
                    return Scaled(name, (s.time.array() >= on && s.time.array() < off).cast<double>().matrix(), scale);
                  },
                  nullptr, ScanWindow, {}, {}});
  rows.back().words = [](const FactorParameters& p, double k, const std::string& u, const std::string&, const std::string&) {
    return fmt::format("changes between {:.4g} s and {:.4g} s by {:+.4g}{}", Value(p, "on_time"), Value(p, "off_time"),
                       k, u);
  };
  rows.back().nests = {"time_step"};  // opened before the motion starts, or closed after it ends
  rows.push_back({"time_warm_up", "{}_warm_up", "settling as the machine warms", "1 − exp(−(t − t_s)/T)",
                  "a temperature following the heat put in through a thermal time constant",
                  {{"start_time", "s", "t_s: the record's first instant"},
                   {"time_constant", "s", "T: 63 % of the change at t_s + T"}},
                  false, Periodicity::kNone,
                  [](EffectTraits* t) { t->refined_parameter = "time_constant"; },
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    return Scaled(name, WarmUp(s.time, Need(p, "start_time", name), NeedPositive(p, "time_constant", name)),
                                  scale);
                  },
                  nullptr, ScanWarmUp, {}, {}});
  rows.back().words = [](const FactorParameters& p, double k, const std::string& u, const std::string&, const std::string&) {
    return fmt::format("settles with T = {:.3g} s by {:+.4g}{}", Value(p, "time_constant"), k, u);
  };
  rows.push_back({"time_periodic", "{}_vibration", "vibrating in time", "cos(2πkft), sin(2πkft), k = 1..K",
                  "a vibration of its own frequency: a pump, a fan, a neighbouring machine, a supply's ripple",
                  {{"frequency_hz", "Hz", "f: the vibration's fundamental"}, {"harmonics", "", "K, 1 when absent"}},
                  false, Periodicity::kTime,
                  // Within ±1 %: the periodogram's peak is that close, and the joint fit's error ripples in f with a
                  // period of 1/T (the record's length), so a wider scan would land on a side lobe.
                  [](EffectTraits* t) {
                    t->refined_parameter = "frequency_hz";
                    t->refinement_range = 1.01;
                  },
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    const auto harmonics = p.find("harmonics");
                    return PeriodicColumns(s.time, 1.0 / NeedPositive(p, "frequency_hz", name),
                                           harmonics == p.end() ? 1 : std::max(1, static_cast<int>(harmonics->second)),
                                           name, scale);
                  },
                  nullptr, ScanTimePeriod, {}, {}});
  rows.back().words = [](const FactorParameters& p, double, const std::string&, const std::string&, const std::string&) {
    return fmt::format("vibrates in time at {:.4g} Hz", Value(p, "frequency_hz"));
  };
  rows.push_back({"time_chirp", "{}_drifting_vibration", "vibrating at a frequency drifting in time",
                  "cos kφ, sin kφ, φ = 2π(f₀t + ½ḟt²), k = 1..K",
                  "a vibration whose frequency drifts: a pump or a fan speeding up, a neighbouring machine changing speed",
                  {{"frequency_hz", "Hz", "f₀: the vibration's frequency at t = 0"},
                   {"drift_rate", "Hz/s", "ḟ: how fast its frequency changes"},
                   {"harmonics", "", "K, 1 when absent"}},
                  false, Periodicity::kTime, nullptr,
                  [](const FactorParameters& p, const DiagnosisSignals& s, const std::string& name,
                     const Eigen::VectorXd* scale) {
                    const auto harmonics = p.find("harmonics");
                    return PeriodicColumns(ChirpCycles(s.time, Need(p, "frequency_hz", name), Need(p, "drift_rate", name)),
                                           1.0, harmonics == p.end() ? 1 : std::max(1, static_cast<int>(harmonics->second)),
                                           name, scale);
                  },
                  nullptr,
                  [](ProposalContext& c, const Eigen::VectorXd& m, const Eigen::VectorXd*, const std::string& pair) {
                    return ScanTimeChirp(c, m, pair);
                  },
                  {}, {}});
  rows.back().words = [](const FactorParameters& p, double, const std::string&, const std::string&, const std::string&) {
    return fmt::format("vibrates in time at {:.4g} Hz {:+.4g} Hz/s·t", Value(p, "frequency_hz"), Value(p, "drift_rate"));
  };
  return rows;
}

}  // namespace

std::pair<double, double> TimeScanRange(std::string_view parameter, const Eigen::VectorXd& time) {
  if (time.size() < 2) return {0.0, 0.0};
  const double t0 = time(0), duration = time(time.size() - 1) - t0;
  const double trim = parameter == "change_time" ? kTimeTrim : 0.5 * kTimeTrim;
  return {t0 + trim * duration, t0 + (1.0 - trim) * duration};
}

const std::vector<MultiplierRow>& Multipliers() {
  static const std::vector<MultiplierRow> rows = MakeMultipliers();
  return rows;
}

const std::vector<ModulatorRow>& Modulators() {
  static const std::vector<ModulatorRow> rows = MakeModulators();
  return rows;
}

const MultiplierRow* FindMultiplier(std::string_view id) {
  for (const MultiplierRow& r : Multipliers()) {
    if (id == r.id) return &r;
  }
  return nullptr;
}

const ModulatorRow* FindModulator(std::string_view id) {
  for (const ModulatorRow& r : Modulators()) {
    if (id == r.id) return &r;
  }
  return nullptr;
}

std::string PairName(const MultiplierRow& multiplier, const ModulatorRow& modulator) {
  return fmt::format(fmt::runtime(modulator.name_pattern), multiplier.noun);
}

std::string PairWords(const MultiplierRow& m, const ModulatorRow& mod, const FactorParameters& p,
                      double coefficient, const std::string& column, const std::string& position_unit) {
  return fmt::format("{} {}", m.phrase, mod.words(p, coefficient, m.unit, column, position_unit));
}

}  // namespace mb

namespace mb {

namespace {

// Text for a Markdown table cell: its bars escaped (|v| would end the cell).
std::string Cell(std::string_view text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += '\\';
    out += ch;
  }
  return out;
}

}  // namespace

std::string GrammarMarkdown() {
  std::string out = "| multiplier | what the force is proportional to | columns | usually |\n|---|---|---|---|\n";
  for (const MultiplierRow& m : Multipliers()) {
    out += fmt::format("| `{}` | {} | {} | {} |\n", m.id, Cell(m.phrase), Cell(m.formula), Cell(m.physics));
  }
  out += "\n| modulator | what it varies with | columns | shape parameters | usually |\n|---|---|---|---|---|\n";
  for (const ModulatorRow& mod : Modulators()) {
    std::string parameters;
    for (const EffectParameter& p : mod.parameters) {
      parameters += fmt::format("{}{} [{}]", parameters.empty() ? "" : ", ", p.name, p.unit.empty() ? "–" : p.unit);
    }
    out += fmt::format("| `{}` | {} | {} | {} | {} |\n", mod.id, *mod.phrase == '\0' ? "nothing (a constant)" : mod.phrase,
                       Cell(mod.formula), parameters.empty() ? "–" : parameters,
                       mod.physics[0] == '\0' ? "–" : Cell(mod.physics));
  }
  out += "\nEvery pair, by the name the diagnosis gives it (a hand-written effect of the catalogue where one holds the "
         "pair):\n\n| multiplier \\ modulator |";
  for (const ModulatorRow& mod : Modulators()) out += fmt::format(" `{}` |", mod.id);
  out += "\n|---|";
  for (std::size_t k = 0; k < Modulators().size(); ++k) out += "---|";
  out += "\n";
  std::map<std::pair<std::string, std::string>, std::string> held;
  for (const EffectType* e : EffectRegistry::Global().Effects()) {
    if (!e->multiplier.empty()) held[{e->multiplier, e->modulator}] = e->name;
  }
  for (const MultiplierRow& m : Multipliers()) {
    out += fmt::format("| `{}` |", m.id);
    for (const ModulatorRow& mod : Modulators()) {
      const auto it = held.find({m.id, mod.id});
      out += fmt::format(" {} |", it == held.end() ? "—" : it->second);
    }
    out += "\n";
  }
  return out;
}

}  // namespace mb
