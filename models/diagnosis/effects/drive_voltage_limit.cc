// drive_voltage_limit: the drive runs out of voltage at speed (back-EMF). A motor winding of resistance R driven from a
// bus of voltage V_bus turns a current into force with k_t while its motion induces k_e·v against the supply: in
// steady state the current loop can drive at most i = (±V_bus − k_e·v)/R, so the force the drive delivers lies in
// [L₋ − k·v, L₊ − k·v] with L± = ±k_t·V_bus/R its limits at standstill and k = k_t·k_e/R the speed slope (the limit
// falls while the motor drives in the direction of motion and rises while it brakes; a Saturation Dynamic in Simulink's
// words). In equation-error mode the model's force ŷ from the motion is the force that acted, and the residual is the
// part of the logged command u the drive did not deliver: u − clamp(u, L₋ − k·v, L₊ − k·v), 0 inside the limits.
// Regressor that excess {upper_limit L₊, lower_limit L₋ [unit of the command], speed_slope k [unit of the command per
// unit of velocity]; reported besides: no_load_speed L₊/k, the speed at which the drive can no longer push}; it is the
// error itself (coefficient 1). With w = u + k·v the excess is w − clamp(w, L₋, L₊): for each slope the limits are
// drive_saturation's. Proposal: the residual minus the excess (coefficient 1) refit on the base, the slope scanned over
// a log grid of k·max|v| from 2 % to 100 % of the |u| that 0.5 % of the samples pass (then golden section), with one
// symmetric limit scanned for each (as drive_saturation's), then each side with the other held. Proposed only when
// (1) the slope is inside the scanned range (at the low end the limit is drive_saturation's constant one), (2) it fits
// better than the best constant limit by at least 25 % of what that limit leaves (a speed dependence the record
// shows, not the noise of the transients), (3) the pair explains at least 2 % of the residual's sum of squares, and
// (4) a side passes the physical test that drive_saturation's sides pass: the regressor is built from the compared
// output itself, so beyond the limit the log must exceed the force the motion shows acted (the model's, from the
// measured motion, u − r after the base refit) by more than the noise — the median of r over the samples beyond at
// least three robust noise levels (1.4826·MAD of r); at least 0.5 % of the samples beyond. Needs the logged command
// (DiagnosisSignals::logged_command, equation-error mode). Block: speed_dependent_saturation on the command path, reading
// the velocity (BlockPlacement::kOnCommand, blocks/speed_dependent_saturation.cc). Sources: DIAGNOSIS.md, "Drive
// saturation"; a DC/brushless motor's voltage equation V = R·i + L·di/dt + k_e·v (e.g. Hughes & Drury, "Electric Motors
// and Drives", 4th ed., §3.4, the torque–speed limit of a voltage-limited drive).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/command_limit.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/robust_weighting.h"

namespace mb {
namespace {

constexpr const char* kName = "drive_voltage_limit";
constexpr double kMinExplained = 0.02;     // of the residual's sum of squares
constexpr double kSlopeLow = 0.02, kSlopeHigh = 1.0;  // k·max|v| as a fraction of the command's high quantile
constexpr int kSlopeGrid = 15;
constexpr double kMinSlopeGain = 0.25;  // of what the best constant limit leaves unexplained

// u − clamp(u, lower − k·v, upper − k·v): what the log holds beyond the limits at each speed.
Eigen::VectorXd Excess(const Eigen::VectorXd& u, const Eigen::VectorXd& v, double slope, double lower, double upper) {
  const Eigen::VectorXd w = u + slope * v;
  return w - w.cwiseMax(lower).cwiseMin(upper);
}

struct Limits {
  double slope = 0.0, lower = 0.0, upper = 0.0;
  std::optional<double> kept_lower, kept_upper;
  std::string refused;  ///< why it is not proposed, for the report's notes ("" = proposed, or nothing to say)
};

// The scans' fits run on the samples moving faster than the dead band (ProposalContext::dead_band): at rest the
// command stays inside any limit (w = u there), so no limit is told by them, while the model's Coulomb law chatters on
// the velocity noise (±F_c, the friction law near zero velocity) and, refit with the base, pulled the slope down (127
// for 225 N·s/m on the independent back-EMF log). The physical test reads every sample.
class Scan {
 public:
  explicit Scan(const ProposalContext& c) : c_(c) {
    const DiagnosisSignals& s = c.signals();
    const Eigen::MatrixXd base = c.BaseWithConstant();
    std::vector<Eigen::Index> moving;
    for (Eigen::Index i = 0; i < c.size(); ++i) {
      if (std::abs(s.velocity(i)) > c.dead_band()) moving.push_back(i);
    }
    const auto m = static_cast<Eigen::Index>(moving.size());
    u_.resize(m);
    v_.resize(m);
    r_.resize(m);
    base_.resize(m, base.cols());
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index i = moving[static_cast<std::size_t>(k)];
      u_(k) = s.logged_command(i);
      v_(k) = s.velocity(i);
      r_(k) = c.residual()(i);
      base_.row(k) = base.row(i);
    }
    gram_ = base_.transpose() * base_;
    none_.resize(m, 0);
  }

  Eigen::Index size() const { return u_.size(); }
  // The base refit's sum of squares of the residual less the excess (its physical coefficient 1), moving samples.
  double Sse(double slope, double lower, double upper) const {
    const Eigen::VectorXd r = r_ - Excess(u_, v_, slope, lower, upper);
    return JointFitResidual(base_, gram_, r)(none_);
  }
  double BaseSse() const { return ResidualSumOfSquares(base_, none_, r_); }
  // The best symmetric limit for `slope` over [median |w|, the |w| that 0.5 % pass]; 0 when that range is empty.
  double SymmetricLimit(double slope) const {
    const auto [lo, hi] = LimitScanRange(u_ + slope * v_);
    if (!(hi > lo && lo > 0.0)) return 0.0;
    return MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return Sse(slope, -l, l); }, true);
  }
  double SymmetricSse(double slope) const {
    const double l = SymmetricLimit(slope);
    return l > 0.0 ? Sse(slope, -l, l) : BaseSse();
  }
  // Over every sample: the physical test of the side (LogExceedsActedForce).
  bool SidePasses(double slope, double limit, double side) const {
    const DiagnosisSignals& s = c_.signals();
    return LogExceedsActedForce(c_.residual(), side, [&](Eigen::Index i) {
      return side * (s.logged_command(i) + slope * s.velocity(i)) > side * limit;
    });
  }
  const Eigen::VectorXd& u() const { return u_; }
  const Eigen::VectorXd& v() const { return v_; }

 private:
  const ProposalContext& c_;
  Eigen::VectorXd u_, v_, r_;  // the moving samples' command, velocity and residual
  Eigen::MatrixXd base_;       // their rows of the base (with a constant)
  Eigen::MatrixXd gram_;       // BᵀB once for the scans (N·p² each time otherwise)
  Eigen::MatrixXd none_;
};

Limits ScanLimits(const ProposalContext& c) {
  const Scan scan(c);
  if (scan.size() < 2) return {};
  const double max_speed = scan.v().cwiseAbs().maxCoeff();
  const auto [median_u, high_u] = LimitScanRange(scan.u());
  if (!(max_speed > 0.0 && high_u > median_u && median_u > 0.0)) return {};
  const double slope_lo = kSlopeLow * high_u / max_speed, slope_hi = kSlopeHigh * high_u / max_speed;
  Limits out;
  out.slope = MinimiseOnLogGrid(slope_lo, slope_hi, kSlopeGrid, 20, [&](double k) { return scan.SymmetricSse(k); });
  const double grid_ratio = std::pow(slope_hi / slope_lo, 1.0 / (kSlopeGrid - 1));
  const double sloped_sse = scan.SymmetricSse(out.slope), constant_sse = scan.SymmetricSse(0.0);
  const double base_sse = scan.BaseSse();
  if (!(out.slope > slope_lo * std::sqrt(grid_ratio))) return out;  // the constant limit: drive_saturation's
  if (!(constant_sse - sloped_sse >= kMinSlopeGain * constant_sse)) {
    out.refused = fmt::format("drive_voltage_limit not proposed: a limit falling with speed (best slope {:.4g}) removes "
                              "only {:.1f} % of what a constant limit leaves of the residual (the moving samples' sum of "
                              "squares {:.4g} of {:.4g}, {:.4g} before any limit): a constant limit is drive_saturation",
                              out.slope, 100.0 * (1.0 - sloped_sse / constant_sse), sloped_sse, constant_sse,
                              base_sse);
    return out;
  }
  const double symmetric = scan.SymmetricLimit(out.slope);
  const auto [lo, hi] = LimitScanRange(scan.u() + out.slope * scan.v());
  out.upper = MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return scan.Sse(out.slope, -symmetric, l); }, true);
  out.lower = -MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return scan.Sse(out.slope, -l, out.upper); }, true);
  if (!(scan.Sse(out.slope, out.lower, out.upper) < (1.0 - kMinExplained) * base_sse)) return out;
  if (scan.SidePasses(out.slope, out.upper, 1.0)) out.kept_upper = out.upper;
  if (scan.SidePasses(out.slope, out.lower, -1.0)) out.kept_lower = out.lower;
  if (!out.kept_upper && !out.kept_lower) {
    const double noise = diagnosis_detail::RobustScale(c.residual());
    out.refused = fmt::format("drive_voltage_limit not proposed: beyond the best limits ({:.4g}, {:.4g}) − {:.4g}·v the "
                              "logged command exceeds the force the motion shows acted by no more than the noise "
                              "({:.3g} robust RMS)",
                              out.lower, out.upper, out.slope, noise);
  }
  return out;
}

void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (s.logged_command.size() != c.size() || s.velocity.size() != c.size()) return;
  const Limits limits = ScanLimits(c);
  if (!limits.refused.empty()) c.Note(limits.refused);
  if (!limits.kept_upper && !limits.kept_lower) return;
  // A side without saturation: a limit beyond the record (at any of its speeds), so that the block leaves it alone.
  const Eigen::VectorXd w = s.logged_command + limits.slope * s.velocity;
  const double span = w.maxCoeff() - w.minCoeff();
  const double upper = limits.kept_upper.value_or(w.maxCoeff() + span);
  c.Propose(kName, {{"upper_limit", upper},
                    {"lower_limit", limits.kept_lower.value_or(w.minCoeff() - span)},
                    {"speed_slope", limits.slope},
                    {"no_load_speed", upper / limits.slope}});
}

EffectType DriveVoltageLimit() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 113;
  t.physics = "the drive runs out of voltage at speed (back-EMF): the force it can deliver falls with the speed in the "
              "direction it drives, while the logged command goes beyond; add a speed_dependent_saturation on the "
              "command path (or a higher bus voltage, a winding of lower back-EMF constant)";
  t.regressor_formula = "u − clamp(u, L₋ − k·v, L₊ − k·v), u the logged command";
  t.parameters = {{"upper_limit", "", "L₊: the largest command the drive delivers at standstill [unit of the command]"},
                  {"lower_limit", "", "L₋: the most negative command the drive delivers at standstill [unit of the "
                                      "command]"},
                  {"speed_slope", "", "k = k_t·k_e/R: how fast the limits fall with the speed [unit of the command "
                                      "per unit of velocity, N·s/m on a linear axis]"},
                  {"no_load_speed", "m/s", "L₊/k: the speed at which the drive can no longer push forward"}};
  t.traits.regressor_is_error = true;
  t.traits.regressor_in_output_band = true;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    if (s.logged_command.size() != s.size()) {
      throw std::invalid_argument(fmt::format("effect '{}' needs the logged command (equation-error mode)", e.name));
    }
    const double upper = RequiredParameter(e, "upper_limit"), lower = RequiredParameter(e, "lower_limit");
    const double slope = RequiredParameter(e, "speed_slope");
    if (!(lower < upper)) {
      throw std::invalid_argument(fmt::format("effect '{}': lower_limit {} must lie below upper_limit {}", e.name,
                                              lower, upper));
    }
    if (!(slope >= 0.0)) {
      throw std::invalid_argument(fmt::format("effect '{}': speed_slope {} must be ≥ 0 (a back-EMF lowers the limit "
                                              "in the direction of motion)",
                                              e.name, slope));
    }
    return SingleColumn(e.name, Excess(s.logged_command, s.velocity, slope, lower, upper));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(drive_voltage_limit, mb::DriveVoltageLimit())
