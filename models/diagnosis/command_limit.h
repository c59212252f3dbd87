#pragma once
// What the drive limits built from the logged command share (effects/drive_saturation.cc: u − clamp(u, L₋, L₊);
// effects/drive_voltage_limit.cc: the same with limits that fall with speed). Their regressor is built from the
// compared output itself, so on a record that never saturates it fits the measurement's noise (issue 40: "explains
// 63 %" with a held-out error 3 × below the noise floor). A limit is physical only when, beyond it, the log exceeds the
// force the motion shows acted — the model's force from the measured motion after the base refit, u − r — by more than
// the noise. Source: DIAGNOSIS.md, "Drive saturation"; docs/diagnosis.md, the leak guard.

#include <functional>
#include <utility>

#include <Eigen/Core>

namespace mb {

/// Of the samples: fewer beyond a limit are the noise's extremes, no saturation.
inline constexpr double kMinShareBeyondLimit = 0.005;

/// The range a limit is scanned over: |values| at the median and at the quantile that kMinShareBeyondLimit of the
/// samples pass (the values in the command's unit). Precondition: values not empty.
std::pair<double, double> LimitScanRange(const Eigen::VectorXd& values);

/// The physical test of one side (+1 above L₊, −1 below L₋) of a limit: at least kMinShareBeyondLimit of the samples
/// lie beyond it (`beyond(i)`), and over them the median of side·r — what the log holds beyond the force that acted —
/// is at least three robust noise levels of r (σ = 1.4826·MAD, diagnosis_detail::RobustScale). `residual` N [the
/// command's unit], the base-refit residual.
bool LogExceedsActedForce(const Eigen::VectorXd& residual, double side,
                          const std::function<bool(Eigen::Index)>& beyond);

}  // namespace mb
