#pragma once
// How closely a record places the time of a chosen effect's change: a step's change time, a window's edges
// (change_time_interval.cc; DiagnoseMissingEffects, step 5′).

#include <cstddef>
#include <string>
#include <vector>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

/// The stretch of the record's time [s] that one change time of an effect may lie in, and where in it the effect's
/// change time was placed.
struct TimeInterval {
  std::string parameter;         ///< "change_time", "on_time" or "off_time"
  double low = 0.0, high = 0.0;  ///< [s], on the record's clock; low ≤ both estimates ≤ high
  double best_fit = 0.0;         ///< [s]: the time of the lowest sum of squares (the selection's shape scan)
  double estimate = 0.0;         ///< [s]: the time the effect now holds, best_fit or the posterior median
};

/// Each change time of the chosen effect `ranked->chosen.order[position]` (the parameters change_time, on_time,
/// off_time its instance holds), as an interval: the profile of the joint fit over that time. The time is moved over a
/// grid of kProfileGrid points across the record (a window's other edge kept on its side), those outside the stretch
/// its scan searched left out (TimeScanRange: a step's middle 80 % of the record, a window's middle 90 %), the effect's
/// columns rebuilt there (EffectType::regressors on `signals`, filtered like a candidate's: FilterCandidateColumns) and
/// every coefficient refit with them beside the other chosen columns, under the ranking's robust weights; the interval
/// is the hull of the estimate and every grid point whose weighted sum of squares stays within χ²₁(0.95) = 3.84
/// long-run variances of the lowest (a profile with two minima the record cannot choose between spans both), its ends
/// bisected to 1/256 of a grid step and then widened to the samples on either side (the columns change only where the
/// time crosses a sample). The long-run variance is the final weighted residual's, from `options.significance_batches`
/// contiguous batch means (its autocorrelation counted, as the significance test counts it), so that a change inside a
/// stretch where the effect's multiplier is nearly zero — a drag that steps while the axis rests — is said to lie
/// anywhere in that stretch rather than at the scan's minimum.
///
/// Where the interval spans kResolvedCells grid steps or more, the profile is nearly flat over it and its lowest point
/// is an accident of the noise, at either end as likely as inside (a drag switched on while the axis rests was placed
/// where the previous move ended, 0.9 s before the next one it acts in). The change time is then moved to the
/// profile's posterior median — the likelihood exp(−Δ/(2σ²)) with σ² the long-run variance, a flat prior over the
/// grid — which minimises the expected absolute error (Smith, "A Bayesian approach to inference about a change-point
/// in a sequence of random variables", Biometrika 62(2), 1975), provided the median's own sum of squares lies within
/// the interval's level (between two minima it may not: the best fit stays). The candidate's instance, columns and
/// scale are updated in `ranked->m`; call before the final joint fit.
/// Source: the likelihood-ratio interval for a change point (Hinkley, "Inference about the change-point in a sequence
/// of random variables", Biometrika 57(1), 1970; Siegmund, "Confidence sets in change-point problems", International
/// Statistical Review 56(1), 1988), χ²₁ its usual approximation. Empty when the effect has no change time. Throws
/// nothing of its own: a grid point whose columns cannot be computed (std::invalid_argument) is left out of the run.
std::vector<TimeInterval> PlaceChangeTimes(Ranking* ranked, std::size_t position, const DiagnosisSignals& signals,
                                           const DiagnosisOptions& options);

}  // namespace mb::diagnosis_detail
