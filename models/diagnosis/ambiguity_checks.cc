// Ambiguity checks (DiagnoseMissingEffects, step 6). Position- vs time-periodic: at one steady speed a period P in
// position is a period P/|v| in time and the two hypotheses have the same regressors; the top periodic effect is refit
// against its counterpart under the other hypothesis at the record's mean speed, and when their shares are too close
// the diagnosis says it cannot tell (and asks for a record at two or more speeds). Hysteresis: the residual moving
// forward minus moving back, per position bin, varying over the travel beyond its sampling error. Source: DIAGNOSIS.md,
// "Naming the missing effect", step 2 ("say 'cannot tell' when the data cannot"), and "When the base model is wrong
// elsewhere" (position vs time by the record's own speed changes; hysteresis loops against position).
#include "models/diagnosis/ambiguity_checks.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/QR>
#include <fmt/format.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/diagnosis_text.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb::diagnosis_detail {
namespace {

bool IsPeriodic(const std::string& effect) { return LookupEffect(effect).traits.periodicity != Periodicity::kNone; }

// How far the record's position strays from uniform motion x ≈ x₀ + v̄·t (least squares): v̄ and the RMS deviation.
struct UniformMotionFit {
  double mean_velocity = 0.0, rms_deviation = 0.0;
};

UniformMotionFit FitUniformMotion(const DiagnosisSignals& signals) {
  const Eigen::VectorXd t = signals.time.array() - signals.time.mean();
  const Eigen::VectorXd x = signals.position.array() - signals.position.mean();
  UniformMotionFit out;
  out.mean_velocity = t.dot(x) / t.squaredNorm();
  out.rms_deviation = std::sqrt((x - out.mean_velocity * t).squaredNorm() / static_cast<double>(x.size()));
  return out;
}

// The registered effect that is the plain Fourier series in x (Periodicity::kPosition, parameters "period" and
// "harmonics") or in t (kTime, "frequency_hz" and "harmonics"), asked of the registry by what the counterpart is rather
// than by name (a speed-scaled ripple, periodic in x too, declares no harmonics); the first in catalogue order, nullptr
// when none is registered.
const EffectType* FourierSeriesEffect(Periodicity periodicity, const std::string& abscissa_parameter) {
  for (const EffectType* type : EffectRegistry::Global().Effects()) {
    if (type->traits.periodicity != periodicity || type->parameters.size() != 2) continue;
    const auto declares = [&](const std::string& name) {
      return std::any_of(type->parameters.begin(), type->parameters.end(),
                         [&](const EffectParameter& p) { return p.name == name; });
    };
    if (declares(abscissa_parameter) && declares("harmonics")) return type;
  }
  return nullptr;
}

// The counterpart of a periodic effect under the other hypothesis at the record's mean speed v̄: position period P ↔
// time frequency |v̄|/P (FourierSeriesEffect). Empty name when there is none (v̄ = 0, or no such effect registered).
EffectInstance Counterpart(const DiagnosedEffect& e, double mean_speed) {
  const auto harmonics = e.parameters.count("harmonics") ? e.parameters.at("harmonics") : 1.0;
  if (!(mean_speed > 0.0)) return {};
  if (LookupEffect(e.effect).traits.periodicity == Periodicity::kTime) {
    const EffectType* in_position = FourierSeriesEffect(Periodicity::kPosition, "period");
    if (in_position == nullptr) return {};
    return {in_position->name,
            {{"period", mean_speed / e.parameters.at("frequency_hz")}, {"harmonics", harmonics}}};
  }
  const EffectType* in_time = FourierSeriesEffect(Periodicity::kTime, "frequency_hz");
  if (in_time == nullptr) return {};
  return {in_time->name, {{"frequency_hz", mean_speed / e.parameters.at("period")}, {"harmonics", harmonics}}};
}

// The first effect named outside the friction-law replacements, or nullptr.
DiagnosedEffect* FirstOutsideTheLaws(DiagnosisResult* result) {
  for (auto& e : result->effects) {
    if (std::find(result->friction_law.begin(), result->friction_law.end(), e.effect) == result->friction_law.end()) {
      return &e;
    }
  }
  return nullptr;
}

}  // namespace

std::string CheckPositionTimeAmbiguity(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                       const Eigen::MatrixXd& base, const DiagnosisOptions& options,
                                       DiagnosisResult* result) {
  const DiagnosedEffect* top = nullptr;
  for (const auto& e : result->effects) {
    if (!top && IsPeriodic(e.effect)) top = &e;
  }
  if (!top) return {};
  const UniformMotionFit uniform = FitUniformMotion(signals);
  const double mean_speed = signals.velocity.cwiseAbs().mean();
  // Monotone motion: its average speed; back and forth: the mean |v|.
  const double speed = std::abs(uniform.mean_velocity) > 0.5 * mean_speed ? std::abs(uniform.mean_velocity) : mean_speed;
  const EffectInstance other = Counterpart(*top, speed);
  if (other.name.empty()) return {};
  const double total = (residual.array() - residual.mean()).matrix().squaredNorm();
  const auto share = [&](const EffectInstance& e) {
    return 1.0 - JointFitResidual(base, residual, options.catalogue.loop.get())(BuildEffectRegressors(e, signals).columns) / total;
  };
  const double own = share({top->effect, top->parameters}), alternative = share(other);
  const bool in_time = LookupEffect(top->effect).traits.periodicity == Periodicity::kTime;
  const double period = in_time ? speed / top->parameters.at("frequency_hz") : top->parameters.at("period");
  const double phase = 2.0 * std::numbers::pi * uniform.rms_deviation / period;
  const std::string evidence = fmt::format(
      "{} explains {:.1f} % of the base-refit residual, {} at the frequency of the mean speed {:.4g} {}/s {:.1f} %; the "
      "position strays {:.2g} rad of phase RMS from uniform motion at the period",
      top->effect, 100.0 * own, other.name, speed, options.position_unit, 100.0 * alternative, phase);
  if (std::abs(own - alternative) >= options.position_time_margin * std::max(own, alternative)) {
    result->notes.push_back(fmt::format(
        "position- vs time-periodic told apart by how the residual follows the speed: it follows {} ({})",
        own >= alternative ? (in_time ? "time, not the position" : "the position, not time")
                           : (in_time ? "the position better than time" : "time better than the position"),
        evidence));
    return {};
  }
  result->position_time_indistinguishable = true;
  std::string note = fmt::format(
      "cannot tell position-periodic from time-periodic: the motion has essentially one speed ({}), so a period P in "
      "position is a period P/|v| in time. Record the motion at two or more speeds to tell them apart.",
      evidence);
  result->notes.push_back(note);
  for (auto& e : result->effects) {
    if (IsPeriodic(e.effect)) e.description += " (position-periodic vs time-periodic: cannot tell at one speed)";
  }
  return note;
}

namespace {

// `top` as the product `name` of its modulator: its shape as found; a friction's slip velocity as found, else the dead
// band's.
EffectInstance AsProduct(const DiagnosedEffect& top, const std::string& name, double dead_band) {
  EffectInstance out{name, top.parameters};
  for (const auto& p : LookupEffect(name).parameters) {
    if (p.name == "slip_velocity" && !out.parameters.count("slip_velocity")) {
      out.parameters["slip_velocity"] = std::max(dead_band, 1e-12);
    }
  }
  return out;
}

// AsProduct(top, name, dead_band) as a diagnosed effect, its columns fitted beside the base on `residual` (least
// squares: the coefficients `improve` starts from; in simulation mode the columns are forces passed through the closed
// loop first, options.catalogue.loop, so that the coefficients are the force's); nullopt where it has no columns on
// this record.
std::optional<DiagnosedEffect> AlikeEffect(const DiagnosedEffect& top, const std::string& name, double dead_band,
                                           const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                           const Eigen::MatrixXd& base, const DiagnosisOptions& options) {
  Candidate c;
  c.type = &LookupEffect(name);
  c.effect = AsProduct(top, name, dead_band);
  try {
    c.reg = c.type->regressors(c.effect, signals);
  } catch (const std::invalid_argument&) {  // not on this record (ŷ in simulation mode)
    return std::nullopt;
  }
  FilterCandidateColumns(*c.type, signals, options, &c.reg.columns);
  const Eigen::Index p = base.cols(), k = c.reg.columns.cols();
  if (k == 0) return std::nullopt;
  Eigen::MatrixXd x(residual.size(), p + k);
  x << base, (options.catalogue.loop ? options.catalogue.loop->Apply(c.reg.columns) : c.reg.columns);
  const Eigen::VectorXd coefficients = x.colPivHouseholderQr().solve(residual).tail(k);
  if (!coefficients.allFinite()) return std::nullopt;
  DiagnosedEffect alike = DescribeEffect(c, top.score, top.cumulative_share, coefficients, Eigen::VectorXd::Zero(k),
                                         signals, options.position_unit, false);
  alike.base_share = top.base_share;
  alike.selection_order = top.selection_order;
  alike.alike = {top.effect};
  return alike;
}

}  // namespace

void CheckMultiplierAmbiguity(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                              const Eigen::MatrixXd& base, const DiagnosisOptions& options, DiagnosisResult* result) {
  DiagnosedEffect* top = FirstOutsideTheLaws(result);
  if (top == nullptr || top->multiplier.empty() || top->modulator.empty()) return;
  const double total = (residual.array() - residual.mean()).matrix().squaredNorm();
  if (!(total > 0.0)) return;
  const auto share = [&](const EffectInstance& e) {
    try {
      const EffectType& type = LookupEffect(e.name);
      Eigen::MatrixXd columns = type.regressors(e, signals).columns;
      FilterCandidateColumns(type, signals, options, &columns);
      return 1.0 - JointFitResidual(base, residual, options.catalogue.loop.get())(columns) / total;
    } catch (const std::invalid_argument&) {  // not on this record (ŷ in simulation mode, a missing parameter)
      return -1.0;
    }
  };
  const double own = share({top->effect, top->parameters});
  if (!(own > 0.0)) return;
  // Every other product of the same modulator (AsProduct).
  const double dead_band = options.catalogue.dead_band_fraction * signals.velocity.cwiseAbs().maxCoeff();
  std::string best;
  double best_share = -1.0;
  for (const std::string& name : EffectNames()) {
    const EffectType& type = LookupEffect(name);
    if (name == top->effect || type.modulator != top->modulator || type.multiplier.empty() ||
        type.multiplier == top->multiplier) {
      continue;
    }
    const double s = share(AsProduct(*top, name, dead_band));
    if (s > best_share) {
      best_share = s;
      best = name;
    }
  }
  if (best.empty()) return;
  const std::string evidence =
      fmt::format("{} explains {:.1f} % of the base-refit residual, {} {:.1f} %", top->effect, 100.0 * own, best,
                  100.0 * best_share);
  if (best_share < (1.0 - options.position_time_margin) * own) {
    result->notes.push_back(fmt::format("{} is told from the other products of its modulator: {}", top->effect, evidence));
    return;
  }
  top->alike.push_back(best);
  if (std::optional<DiagnosedEffect> alike = AlikeEffect(*top, best, dead_band, signals, residual, base, options)) {
    top->alike_effects.push_back(std::move(*alike));
  }
  const auto formula = [](const std::string& multiplier) {
    const MultiplierRow* row = FindMultiplier(multiplier);
    return row != nullptr ? std::string(row->formula) : multiplier;
  };
  result->notes.push_back(fmt::format(
      "cannot tell {} from {}: {} (within {:.0f} % of it): the multipliers {} and {} differ too little over this record; "
      "a record where they differ (braking against the motion, at rest, the other direction, other speeds or forces) "
      "would tell",
      top->effect, best, evidence, 100.0 * options.position_time_margin, formula(top->multiplier),
      formula(LookupEffect(best).multiplier)));
  top->description += fmt::format(" (or {}: this record cannot tell them apart)", best);
}

void CheckDelayAgainstHysteresis(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                 const Eigen::MatrixXd& base, const DiagnosisOptions& options,
                                 DiagnosisResult* result) {
  constexpr double kLongDelaySamples = 3.0;  // a delay of fewer sample periods is the sampling's, not a transition
  DiagnosedEffect* top = FirstOutsideTheLaws(result);
  if (top == nullptr || (top->effect != "time_delay" && top->effect != "hysteresis")) return;
  const Eigen::Index n = signals.size();
  if (n < 64) return;
  const double sample_period = MedianTimeStep(signals.time);
  const bool delay_first = top->effect == "time_delay";
  if (delay_first && !(top->parameters.count("delay") && top->parameters.at("delay") > kLongDelaySamples * sample_period)) {
    return;
  }
  // The moving samples, and their halves below and above the median speed: the base and the residual on each.
  const Eigen::VectorXd speed = signals.velocity.cwiseAbs();
  const double dead_band = options.catalogue.dead_band_fraction * speed.maxCoeff();
  std::vector<Eigen::Index> moving;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (speed(i) > dead_band) moving.push_back(i);
  }
  if (moving.size() < 64) return;
  std::vector<double> speeds;
  for (Eigen::Index i : moving) speeds.push_back(speed(i));
  std::nth_element(speeds.begin(), speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() / 2), speeds.end());
  const double median = speeds[speeds.size() / 2];
  struct Samples {
    std::vector<Eigen::Index> rows;
    Eigen::MatrixXd base;
    Eigen::VectorXd residual;
    double total = 0.0;  // the residual's centred sum of squares there
  };
  Samples all, slow, fast;
  all.rows = moving;
  for (Eigen::Index i : moving) (speed(i) <= median ? slow : fast).rows.push_back(i);
  for (Samples* h : {&all, &slow, &fast}) {
    h->base = base(h->rows, Eigen::all);
    h->residual = residual(h->rows);
    h->total = (h->residual.array() - h->residual.mean()).matrix().squaredNorm();
    if (!(h->total > 0.0)) return;
  }
  // An effect's columns on this record, or nothing when it cannot be built here; its share of the base-refit residual
  // on a set of samples (its columns refit with the base there).
  const auto columns_of = [&](const EffectInstance& e) -> std::optional<Eigen::MatrixXd> {
    try {
      return BuildEffectRegressors(e, signals).columns;
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  };
  const auto share = [](const Eigen::MatrixXd& columns, const Samples& h) {
    return 1.0 - JointFitResidual(h.base, h.residual)(columns(h.rows, Eigen::all)) / h.total;
  };
  const double travel = signals.position.maxCoeff() - signals.position.minCoeff();
  const std::optional<Eigen::MatrixXd> own = columns_of({top->effect, top->parameters});
  std::optional<Eigen::MatrixXd> other;
  double delay = 0.0;  // the other's, when it is a delay
  if (delay_first) {
    other = columns_of({"hysteresis", {{"min_breakaway", kHysteresisMinBreakawayShare * travel},
                                       {"max_breakaway", kHysteresisMaxBreakawayShare * travel}}});
  } else {  // the delay that fits best over the moving samples, from 2 sample periods to a tenth of the record
    double best = -1.0;
    const double longest = 0.1 * (signals.time(n - 1) - signals.time(0));
    for (double d = 2.0 * sample_period; d <= longest; d *= 1.5) {
      std::optional<Eigen::MatrixXd> columns = columns_of({"time_delay", {{"delay", d}}});
      if (!columns) return;  // no model output on this record
      if (const double s = share(*columns, all); s > best) {
        best = s;
        delay = d;
        other = std::move(columns);
      }
    }
  }
  if (!own || !other) return;
  const double own_slow = share(*own, slow), own_fast = share(*own, fast);
  const double other_slow = share(*other, slow), other_fast = share(*other, fast);
  const std::string other_name = delay_first ? "hysteresis" : "time_delay";
  const std::string evidence = fmt::format(
      "on the moving samples below and above their median speed {:.4g} {}/s, {} explains {:.1f} % and {:.1f} % of the "
      "base-refit residual, {} {:.1f} % and {:.1f} %",
      median, options.position_unit, top->effect, 100.0 * own_slow, 100.0 * own_fast,
      delay_first ? other_name : fmt::format("a delay of {:.3g} s", delay), 100.0 * other_slow, 100.0 * other_fast);
  const double margin = 1.0 - options.position_time_margin;
  if (other_slow >= margin * own_slow && other_fast >= margin * own_fast) {
    top->alike.push_back(other_name);
    top->description += fmt::format(" (or {}: this record cannot tell a delay from hysteresis)", other_name);
    result->notes.push_back(fmt::format(
        "cannot tell a delay from hysteresis: {}; a delay's transition takes a stroke that grows with the speed, "
        "hysteresis' does not — a record at other speeds (another frequency, another amplitude) would tell",
        evidence));
    return;
  }
  result->notes.push_back(fmt::format("delay against hysteresis, told apart by speed: {} ({})",
                                      delay_first ? "a delay" : "hysteresis", evidence));
}

void NoteHysteresis(const DiagnosisSignals& signals, const Eigen::VectorXd& residual, DiagnosisResult* result) {
  const double v_max = signals.velocity.cwiseAbs().maxCoeff();
  const double lo = signals.position.minCoeff(), hi = signals.position.maxCoeff();
  if (!(v_max > 0.0) || !(hi > lo)) return;
  constexpr int kBins = 20;
  Eigen::ArrayXXd sum = Eigen::ArrayXXd::Zero(kBins, 2), sq = sum, count = sum;
  for (Eigen::Index i = 0; i < signals.size(); ++i) {
    const double v = signals.velocity(i);
    if (std::abs(v) < 0.05 * v_max) continue;
    const int b = std::min(kBins - 1, static_cast<int>((signals.position(i) - lo) / (hi - lo) * kBins));
    const int d = v > 0.0 ? 0 : 1;
    sum(b, d) += residual(i); sq(b, d) += residual(i) * residual(i); count(b, d) += 1.0;
  }
  std::vector<double> diff, var;
  for (int b = 0; b < kBins; ++b) {
    if (count(b, 0) < 20 || count(b, 1) < 20) continue;
    const double m0 = sum(b, 0) / count(b, 0), m1 = sum(b, 1) / count(b, 1);
    diff.push_back(m0 - m1);
    var.push_back((sq(b, 0) / count(b, 0) - m0 * m0) / count(b, 0) + (sq(b, 1) / count(b, 1) - m1 * m1) / count(b, 1));
  }
  if (diff.size() < 5) return;
  double mean = 0.0;
  for (double d : diff) mean += d / static_cast<double>(diff.size());
  double spread = 0.0, noise = 0.0;
  for (std::size_t b = 0; b < diff.size(); ++b) { spread += (diff[b] - mean) * (diff[b] - mean); noise += var[b]; }
  const double rms_spread = std::sqrt(spread / static_cast<double>(diff.size()));
  if (spread > 10.0 * noise && rms_spread > 0.1 * result->rmse_after) {
    result->notes.push_back(fmt::format(
        "hysteresis: the residual loops against position — moving forward minus moving back it differs by a "
        "position-dependent {:.3g} (RMS over {} bins, beyond a constant {:.3g}), {:.0f} × its sampling variance: a "
        "force that depends on the direction of travel and the position (magnetic hysteresis, a preloaded guide, a "
        "cable carrier's bending); no catalogue effect models it",
        rms_spread, diff.size(), mean, spread / std::max(noise, 1e-300)));
  }
}

}  // namespace mb::diagnosis_detail
