// drive_saturation: the drive delivers at most its limits — a current limit, a voltage limit at speed — while the
// controller's logged command goes beyond them. In equation-error mode the model's force ŷ (from the motion) is the
// force that acted, clamp(u, L₋, L₊), and the residual is the part of the logged command u that the drive did not
// deliver: u − L₊ where u > L₊, u − L₋ where u < L₋, 0 between (Simulink's Dead Zone of u). Regressor that excess
// {upper_limit L₊, lower_limit L₋ [unit of the command]}; it is the error itself (coefficient 1). Asymmetric limits
// are found side by side; a side the command never passes gets a limit beyond the record. Proposal: a scan of the base
// refit of the residual minus the excess (coefficient 1), one symmetric limit first, then each side (ScanLimits); a
// side is kept when at least 0.5 % of the samples lie beyond it, the pair when it explains at least 2 % of the
// residual's sum of squares. The regressor is built from the compared output itself (the logged command), so a limit
// must first pass a physical test: the drive cannot deliver less than the force the motion shows acted. That force is
// the model's, from the measured motion, after the base refit (u − r); a limit below its extreme quantiles (0.5 %) is
// impossible and is not scanned, and beyond a limit the log must exceed that force by more than three noise levels — on a record that never saturates the
// admissible range is empty, and a limit scanned down to the median |u| would make the regressor the measurement
// itself, noise included (issue 40: "explains 63 %", its held-out error 3× below the noise floor). Needs the logged
// command (DiagnosisSignals::logged_command, equation-error mode). Block:
// saturation on the command path (BlockPlacement::kOnCommand, blocks/saturation.cc). Source: DIAGNOSIS.md, "Drive
// saturation".
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "drive_saturation";
constexpr double kMinShareBeyond = 0.005;  // of the samples beyond a limit: fewer are the noise's extremes
constexpr double kMinExplained = 0.02;     // of the residual's sum of squares

// u − clamp(u, lower, upper): what the log holds beyond the limits.
Eigen::VectorXd Excess(const Eigen::VectorXd& u, double lower, double upper) {
  return u - u.cwiseMax(lower).cwiseMin(upper);
}

// The value of `values` that a share q of them lies below (0 <= q <= 1; nearest rank).
double Quantile(const Eigen::VectorXd& values, double q) {
  std::vector<double> v(values.data(), values.data() + values.size());
  const auto k = static_cast<std::ptrdiff_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

// The physical test: the force that acted (the model's from the measured motion, u − r after the base refit) bounds
// the limits — L₊ at least its upper 0.5 % quantile, L₋ at most its lower one; and beyond a limit the log must hold more
// than the noise: the residual there (what the log holds beyond the force that acted) at least kExcessNoise robust noise
// levels (1.4826·MAD of the residual) in median. A limit in the noise of a force that dwells at its extremes (a
// sinusoid's flat top) would otherwise make the excess the noise of those samples.
constexpr double kExcessNoise = 3.0;

struct ActedForceBounds {
  double min_upper = 0.0, max_lower = 0.0;
  double noise = 0.0;  ///< robust noise level of the residual
};

ActedForceBounds BoundsFromActedForce(const ProposalContext& c) {
  const Eigen::VectorXd acted = c.signals().logged_command - c.residual();
  const double median = Quantile(c.residual(), 0.5);
  const double noise = 1.4826 * Quantile((c.residual().array() - median).abs().matrix(), 0.5);
  return {Quantile(acted, 1.0 - kMinShareBeyond), Quantile(acted, kMinShareBeyond), noise};
}

// Does the log hold more than the noise beyond the limit? The median residual over the samples `beyond` selects,
// signed by the side (+1 above L₊, −1 below L₋).
template <typename Beyond>
bool ExcessAboveNoise(const ProposalContext& c, const ActedForceBounds& bounds, double side, Beyond&& beyond) {
  const Eigen::VectorXd& u = c.signals().logged_command;
  std::vector<double> excess;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    if (beyond(u(i))) excess.push_back(side * c.residual()(i));
  }
  if (excess.empty()) return false;
  const auto middle = excess.begin() + static_cast<std::ptrdiff_t>(excess.size() / 2);
  std::nth_element(excess.begin(), middle, excess.end());
  return *middle >= kExcessNoise * bounds.noise;
}

// The limits: the residual minus the excess (its physical coefficient 1; free, a larger coefficient on a narrower
// excess — a limit too high — fits the peaks as well) refit on the base, scanned for one symmetric limit over
// [median |u|, the |u| that 0.5 % of the samples pass] within the physical bounds, then for each side with the other
// held. A side that fewer than 0.5 % of the samples pass shows no saturation (nullopt).
struct Limits {
  std::optional<double> lower, upper;
  std::string refused;  ///< why no limit is admissible, for the report's notes
};

Limits ScanLimits(const ProposalContext& c) {
  const Eigen::VectorXd& u = c.signals().logged_command;
  const ActedForceBounds bounds = BoundsFromActedForce(c);
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::MatrixXd none(c.size(), 0);
  const Eigen::MatrixXd gram = base.transpose() * base;  // once for the scans (N·p² each time otherwise)
  const auto sse = [&](double lower, double upper) {
    const Eigen::VectorXd r = c.residual() - Excess(u, lower, upper);
    return JointFitResidual(base, gram, r)(none);
  };
  std::vector<double> magnitude(u.data(), u.data() + u.size());
  for (double& m : magnitude) m = std::abs(m);
  std::sort(magnitude.begin(), magnitude.end());
  const auto n = magnitude.size();
  const double lo = magnitude[n / 2], hi = magnitude[n - 1 - static_cast<std::size_t>(kMinShareBeyond * static_cast<double>(n))];
  // The admissible ranges of |L₋| and L₊: above the force that acted.
  const double lo_upper = std::max(lo, bounds.min_upper), lo_lower = std::max(lo, -bounds.max_lower);
  const double lo_symmetric = std::max(lo_upper, lo_lower);
  if (!(lo > 0.0)) return {};
  if (!(hi > lo_upper || hi > lo_lower)) {
    Limits refused;
    refused.refused = fmt::format(
        "drive_saturation not proposed: the force that acted (the model's, from the measured motion) reaches {:.4g} and "
        "{:.4g} where the logged command reaches {:.4g} and {:.4g} (0.5 % quantiles): no drive limit lies between, the "
        "drive delivered what it was commanded",
        bounds.min_upper, bounds.max_lower, hi, -hi);
    return refused;
  }
  // sse is thread-safe (its own vectors per call): the grids in parallel.
  const double symmetric = hi > lo_symmetric
                               ? MinimiseOnLogGrid(lo_symmetric, hi, 21, 20, [&](double l) { return sse(-l, l); }, true)
                               : hi;
  const double upper =
      hi > lo_upper ? MinimiseOnLogGrid(lo_upper, hi, 21, 20, [&](double l) { return sse(-symmetric, l); }, true) : hi;
  const double lower =
      hi > lo_lower ? -MinimiseOnLogGrid(lo_lower, hi, 21, 20, [&](double l) { return sse(-l, upper); }, true) : -hi;
  const double sse_base = ResidualSumOfSquares(base, none, c.residual());
  if (!(sse(lower, upper) < (1.0 - kMinExplained) * sse_base)) return {};
  const auto beyond = [&](auto&& passes) {
    return static_cast<double>((u.array().unaryExpr(passes)).count()) >= kMinShareBeyond * static_cast<double>(n);
  };
  Limits out;
  const auto above = [&](double v) { return v > upper; };
  const auto below = [&](double v) { return v < lower; };
  if (hi > lo_upper && beyond(above) && ExcessAboveNoise(c, bounds, 1.0, above)) out.upper = upper;
  if (hi > lo_lower && beyond(below) && ExcessAboveNoise(c, bounds, -1.0, below)) out.lower = lower;
  if (!out.upper && !out.lower) {
    out.refused = fmt::format("drive_saturation not proposed: beyond the best limits ({:.4g}, {:.4g}) the logged "
                              "command exceeds the force that acted by no more than the noise ({:.3g}): no saturation",
                              lower, upper, bounds.noise);
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
