#pragma once
// Training targets for the TISO-GPR disturbance model that can look ahead: offline, the whole scan is known, so
// the disturbance can be estimated by a smoother instead of the DOB's causal filter. The DOB estimate
// d̂_d = Q∘P_n⁻¹{x} − Q{u} (paper eq. 51) is Q-filtered and therefore lags the disturbance (at the twin's 30 Hz
// Q-filter, 350 mm/s cogging at 15.6 Hz is delayed by ≈ 30°); a GP trained on it learns that phase-shifted
// pattern. The smoothed estimate below applies the same nominal inverse model without phase.
// Part of mb_gpr_log (it uses the zero-phase filter of models/diagnosis/signal_processing.h).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/measurement_log.h"

namespace mb {

/// What the smoothed (non-causal) inverse-model disturbance estimate needs.
struct SmoothedDisturbanceOptions {
  double nominal_mass = 0.0;      ///< M_n [kg] of the nominal plant P_n = 1/(M_n s² + B_n s) (paper eq. 4); > 0
  double nominal_damping = 0.0;   ///< B_n [N·s/m]; ≥ 0
  /// Cut-off [Hz] of the zero-phase low-pass applied to the position (before differentiating) and to the force,
  /// alike; it must lie above the disturbance's band (the twin's cogging at 500 mm/s: 22, 44, 67 Hz) and below the
  /// Nyquist frequency. The quantisation noise of ẍ grows with cutoff².
  double cutoff_hz = 200.0;
  /// The force is held (zero-order hold) over each sample period, as a discrete controller's output is: then
  /// the central second difference of x at t_k matches the mean force (u_{k−1} + u_k)/2 of the two periods around
  /// t_k, and that mean is used (without it the estimate lags by half a sample). false: u is sampled as x is.
  bool force_held = true;
};

/// The smoothed inverse-model disturbance estimate (a non-causal counterpart of the DOB, eq. 51):
///   d̃ = M_n·ẍ + B_n·ẋ − ū
/// with ẋ, ẍ the central differences of the zero-phase low-passed position (DeriveMotion, i.e. the filter run
/// forward and backward as MATLAB/SciPy `filtfilt`), and ū the force low-passed by the same zero-phase filter
/// (after the hold correction above). Same sign as the DOB (d̂_d ≈ Q{d}): for x = P_n(u + d), d̃ ≈ F{d} with F the
/// zero-phase low-pass, |F| = |H|² (−6 dB at the cut-off), phase 0 at every frequency.
/// time [s], position x [m] (the measured encoder position), force u [N] (what the plant received): N ≥ 3
/// samples each, time strictly increasing and evenly sampled (the filter's period is the median step).
/// Returns d̃ [N], N samples.
/// Sources: Gustafsson (1996), "Determining the initial states in forward-backward filtering" (zero-phase
/// filtering); the inverse-model disturbance estimate of Ohnishi's DOB without its causal Q-filter.
/// @throws std::invalid_argument for sizes that differ, N < 3, a time that does not increase, M_n ≤ 0, B_n < 0
/// or non-finite, a cut-off not in (0, Nyquist) (the message says which and how to fix it).
Eigen::VectorXd SmoothedDisturbanceEstimate(const Eigen::Ref<const Eigen::VectorXd>& time,
                                            const Eigen::Ref<const Eigen::VectorXd>& position,
                                            const Eigen::Ref<const Eigen::VectorXd>& force,
                                            const SmoothedDisturbanceOptions& options);

/// The same on a table of concatenated scans: the columns are cut into segments wherever the time does not
/// increase (a new scan restarting at t = 0) or jumps by more than 1.5 median steps (a gap), each segment (≥ 3
/// samples) estimated separately, and the result appended as column `output_column`.
/// @throws std::invalid_argument naming the table's source for a missing column (listing those present), an
/// existing `output_column`, a segment shorter than 3 samples, and as SmoothedDisturbanceEstimate.
void AddSmoothedDisturbanceColumn(Table& table, const std::string& time_column, const std::string& position_column,
                                  const std::string& force_column, const SmoothedDisturbanceOptions& options,
                                  const std::string& output_column);

}  // namespace mb
