#pragma once
// How closely a record places the time of a chosen effect's change: a step's change time, a window's edges
// (change_time_interval.cc; DiagnoseMissingEffects, step 5′).

#include <cstddef>
#include <string>
#include <vector>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

/// The stretch of the record's time [s] that one change time of an effect may lie in.
struct TimeInterval {
  std::string parameter;         ///< "change_time", "on_time" or "off_time"
  double low = 0.0, high = 0.0;  ///< [s], on the record's clock; low ≤ the estimate ≤ high
};

/// Each change time of the chosen effect `ranked.chosen.order[position]` (the parameters change_time, on_time,
/// off_time its instance holds), as an interval: the profile of the final joint fit over that time. The time is moved
/// over a grid of kProfileGrid points across the record (a window's other edge kept on its side), the effect's columns
/// rebuilt there (EffectType::regressors on `signals`, filtered like a candidate's: FilterCandidateColumns) and every
/// coefficient refit with them beside the other chosen columns, under the ranking's robust weights; the interval is the
/// hull of the estimate and every grid point whose weighted sum of squares stays within χ²₁(0.95) = 3.84 long-run
/// variances of the lowest (a profile with two minima the record cannot choose between spans both), its ends bisected
/// to 1/256 of a grid step and then widened to the samples on either side (the columns change only where the time
/// crosses a sample). The long-run variance is the final weighted residual's, from
/// `options.significance_batches` contiguous batch means (its autocorrelation counted, as the significance test
/// counts it), so that a change inside a stretch where the effect's multiplier is nearly zero — a drag that steps
/// while the axis rests — is said to lie anywhere in that stretch rather than at the scan's minimum.
/// Source: the likelihood-ratio interval for a change point (Hinkley, "Inference about the change-point in a sequence
/// of random variables", Biometrika 57(1), 1970; Siegmund, "Confidence sets in change-point problems", International
/// Statistical Review 56(1), 1988), χ²₁ its usual approximation. Empty when the effect has no change time. Throws
/// nothing of its own: a grid point whose columns cannot be computed (std::invalid_argument) is left out of the run.
std::vector<TimeInterval> ProfileChangeTimes(const Ranking& ranked, std::size_t position,
                                             const DiagnosisSignals& signals, const DiagnosisOptions& options);

}  // namespace mb::diagnosis_detail
