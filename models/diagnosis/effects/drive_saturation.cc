// drive_saturation: the drive delivers at most its limits — a current limit, a voltage limit at speed — while the
// controller's logged command goes beyond them. In equation-error mode the model's force ŷ (from the motion) is the
// force that acted, clamp(u, L₋, L₊), and the residual is the part of the logged command u that the drive did not
// deliver: u − L₊ where u > L₊, u − L₋ where u < L₋, 0 between (Simulink's Dead Zone of u). Regressor that excess
// {upper_limit L₊, lower_limit L₋ [unit of the command]}; it is the error itself (coefficient 1). Asymmetric limits
// are found side by side; a side the command never passes gets a limit beyond the record. Proposal: a scan of the base
// refit of the residual minus the excess (coefficient 1), one symmetric limit first, then each side (ScanLimits); a
// side is kept when at least 0.5 % of the samples lie beyond it, the pair when it explains at least 2 % of the
// residual's sum of squares. The regressor is built from the compared output itself (the logged command), so a side
// must first pass a physical test: beyond its limit the log must exceed the force the motion shows acted — the
// model's, from the measured motion, u − r after the base refit — by more than the noise (the median of r over the
// samples beyond at least three robust noise levels, 1.4826·MAD of r). Else the limit sits in the noise of the force's
// extremes (a sinusoid's flat top) and the excess is that noise: on a clean record the limit went down to the median
// |u|, where the regressor is the measurement on half the samples, and "explained 63 %" with a held-out error 3× below
// the noise floor (issue 40). Needs the logged command (DiagnosisSignals::logged_command, equation-error mode). Block:
// saturation on the command path (BlockPlacement::kOnCommand, blocks/saturation.cc). Source: DIAGNOSIS.md, "Drive
// saturation".
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

constexpr const char* kName = "drive_saturation";
constexpr double kMinExplained = 0.02;  // of the residual's sum of squares

// u − clamp(u, lower, upper): what the log holds beyond the limits.
Eigen::VectorXd Excess(const Eigen::VectorXd& u, double lower, double upper) {
  return u - u.cwiseMax(lower).cwiseMin(upper);
}

// The limits: the residual minus the excess (its physical coefficient 1; free, a larger coefficient on a narrower
// excess — a limit too high — fits the peaks as well) refit on the base, scanned for one symmetric limit over
// [median |u|, the |u| that 0.5 % of the samples pass], then for each side with the other held. A side that fewer than
// 0.5 % of the samples pass shows no saturation (nullopt).
struct Limits {
  std::optional<double> lower, upper;
  std::string refused;  ///< why a scanned limit failed the physical test, for the report's notes
};

Limits ScanLimits(const ProposalContext& c) {
  const Eigen::VectorXd& u = c.signals().logged_command;
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::MatrixXd none(c.size(), 0);
  const Eigen::MatrixXd gram = base.transpose() * base;  // once for the scans (N·p² each time otherwise)
  const auto sse = [&](double lower, double upper) {
    const Eigen::VectorXd r = c.residual() - Excess(u, lower, upper);
    return JointFitResidual(base, gram, r)(none);
  };
  const auto [lo, hi] = LimitScanRange(u);
  if (!(hi > lo && lo > 0.0)) return {};
  // sse is thread-safe (its own vectors per call): the grids in parallel.
  const double symmetric = MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return sse(-l, l); }, true);
  const double upper = MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return sse(-symmetric, l); }, true);
  const double lower = -MinimiseOnLogGrid(lo, hi, 21, 20, [&](double l) { return sse(-l, upper); }, true);
  const double sse_base = ResidualSumOfSquares(base, none, c.residual());
  if (!(sse(lower, upper) < (1.0 - kMinExplained) * sse_base)) return {};
  Limits out;
  if (LogExceedsActedForce(c.residual(), 1.0, [&](Eigen::Index i) { return u(i) > upper; })) out.upper = upper;
  if (LogExceedsActedForce(c.residual(), -1.0, [&](Eigen::Index i) { return u(i) < lower; })) out.lower = lower;
  if (!out.upper && !out.lower) {
    const double noise = diagnosis_detail::RobustScale(c.residual());
    out.refused = fmt::format("drive_saturation not proposed: beyond the best limits ({:.4g}, {:.4g}) the logged "
                              "command exceeds the force the motion shows acted by no more than the noise ({:.3g} "
                              "robust RMS): no saturation",
                              lower, upper, noise);
  }
  return out;
}

void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (s.logged_command.size() != c.size()) return;
  const Limits limits = ScanLimits(c);
  if (!limits.refused.empty()) c.Note(limits.refused);
  if (!limits.upper && !limits.lower) return;
  // A side without saturation: a limit beyond the record, so that the block leaves it alone.
  const double span = s.logged_command.maxCoeff() - s.logged_command.minCoeff();
  c.Propose(kName, {{"upper_limit", limits.upper.value_or(s.logged_command.maxCoeff() + span)},
                    {"lower_limit", limits.lower.value_or(s.logged_command.minCoeff() - span)}});
}

EffectType DriveSaturation() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 112;
  t.physics = "the drive saturates: the logged command goes beyond the force it can deliver (current or voltage "
              "limit); add a saturation on the command path";
  t.regressor_formula = "u − clamp(u, L₋, L₊), u the logged command";
  t.parameters = {{"upper_limit", "", "L₊: the largest command the drive delivers [unit of the command]"},
                  {"lower_limit", "", "L₋: the most negative command the drive delivers [unit of the command]"}};
  t.traits.regressor_is_error = true;
  t.traits.regressor_in_output_band = true;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    if (s.logged_command.size() != s.size()) {
      throw std::invalid_argument(fmt::format("effect '{}' needs the logged command (equation-error mode)", e.name));
    }
    const double upper = RequiredParameter(e, "upper_limit"), lower = RequiredParameter(e, "lower_limit");
    if (!(lower < upper)) {
      throw std::invalid_argument(fmt::format("effect '{}': lower_limit {} must lie below upper_limit {}", e.name,
                                              lower, upper));
    }
    return SingleColumn(e.name, Excess(s.logged_command, lower, upper));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(drive_saturation, mb::DriveSaturation())
