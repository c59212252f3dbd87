#pragma once
// The viscous friction changing over a record, in the shapes of time the diagnosis tells apart (DIAGNOSIS.md,
// "Parameters that change"; docs/diagnosis.md, the grammar's time factors): a linear ramp over the record (wear, a slow
// drift: effects/friction_drift.cc), a first-order warm-up that settles inside the record (a lubricant whose
// temperature follows the heat put into it with a thermal time constant, its viscosity falling with the temperature:
// effects/friction_warm_up.cc), and a step at one time (a change of the machine, which neither effect is). Both
// effects share the scan below, so that exactly one of them is proposed for one drift.

#include <Eigen/Core>

#include "models/diagnosis/effect_proposal.h"

namespace mb {

/// v·clamp((t − start)/(end − start), 0, 1): the velocity ramped in over [start, end] [s]. `time`, `velocity` N.
/// Precondition end > start (the callers check).
Eigen::VectorXd RampedVelocity(const Eigen::VectorXd& time, const Eigen::VectorXd& velocity, double start, double end);

/// v·(1 − exp(−(t − start)/T)) for t ≥ start, 0 before: the velocity warmed in with time constant T > 0 [s] from
/// `start` [s] (a first-order lag's step response). `time`, `velocity` N. Precondition T > 0 (the callers check).
Eigen::VectorXd WarmingVelocity(const Eigen::VectorXd& time, const Eigen::VectorXd& velocity, double start,
                                double time_constant);

/// The three shapes fitted to the base-refit residual jointly with the base and a constant (JointFitResidual), each
/// with its best shape parameter; sums of squares in the residual's unit squared.
struct ViscousDriftScan {
  double start = 0.0, end = 0.0;  ///< the record's first and last instants [s]
  double ramp_sse = 0.0;          ///< the ramp over [start, end]
  double step_sse = 0.0;          ///< the best step v·H(t − step_time), 41 times over the middle 80 % of the record
  double step_time = 0.0;         ///< [s]
  double warm_up_sse = 0.0;       ///< the best warm-up from `start`
  double time_constant = 0.0;     ///< its T [s]: log grid of 25 over [duration/100, duration], then golden section
  /// T lies inside the scanned range (not in its first or last grid cell): at the short end the warm-up is a step at
  /// the record's start, at the long end a ramp.
  bool warm_up_inside = false;
  /// A warm-up is the drift: T inside, and it fits better than the ramp and the step.
  bool WarmUpFitsBest() const { return warm_up_inside && warm_up_sse < ramp_sse && warm_up_sse < step_sse; }
};

/// Scans the shapes on the context's residual. Requires a record of positive duration and a velocity that is not all
/// zero (else returns a scan whose sums of squares are all +infinity). Throws nothing of its own.
ViscousDriftScan ScanViscousDrift(const ProposalContext& context);

}  // namespace mb
