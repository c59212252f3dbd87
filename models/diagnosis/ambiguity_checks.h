#pragma once
// What the ranking cannot decide by itself (ambiguity_checks.cc): whether a periodic effect is periodic in position or
// in time, and a residual that loops against position, which no catalogue effect models (DiagnoseMissingEffects,
// step 6).

#include <string>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"

namespace mb::diagnosis_detail {

// 6. Can position-periodic and time-periodic be told apart? By how the residual follows the speed: a position-periodic
// ripple's temporal frequency scales with the speed, a vibration's does not. The top periodic effect is refit (with the
// base) against its counterpart under the other hypothesis at the record's mean speed; when their shares of the
// residual differ by less than options.position_time_margin (relative), the record's speed did not vary enough — at one
// steady speed they are the same regressors — and they cannot be told apart: returns that note and marks the result
// and the effects. Otherwise a note says which one the residual follows.
std::string CheckPositionTimeAmbiguity(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                       const Eigen::MatrixXd& base, const DiagnosisOptions& options,
                                       DiagnosisResult* result);

// 6c. Can the top effect's multiplier be told from the others of its modulator? The first effect outside the friction-law
// replacements, a product of the grammar, is refit alone (with the base) against every other product of the same
// modulator with the same shape (its slip velocity, where it has one, as found or the dead band's); when the best of
// them explains within options.position_time_margin (relative) as much, the record cannot tell the two multipliers
// apart (ŷ and |ŷ|·tanh(v/v_s) where the drive never brakes): a note says so and why, the effect's description names
// the other, DiagnosedEffect::alike holds its name and ::alike_effects the product itself (its columns fitted beside
// the base on `residual`), which `improve` tries in the named one's place on the held-out record. Otherwise a note
// says it was told apart. In simulation mode (options.catalogue.loop) every fit passes the products' forces through the
// closed loop first, as the ranking does. Source: issue 45, item 4.
void CheckMultiplierAmbiguity(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                              const Eigen::MatrixXd& base, const DiagnosisOptions& options, DiagnosisResult* result);

// 6b. Hysteresis: does the residual loop against position — the way out differing from the way back by more than
// a constant (which is Coulomb friction)? Per position bin (20), the mean residual moving forward minus moving back;
// a note when that difference varies over the travel well beyond its sampling error (ratio > 10: the samples are
// autocorrelated) and by more than 10 % of the residual's RMS.
void NoteHysteresis(const DiagnosisSignals& signals, const Eigen::VectorXd& residual, DiagnosisResult* result);

// 6e. A delay against hysteresis, by speed (issue 47): a delay d makes a transition over a stroke v·d that grows with
// the speed; a hysteresis makes it over a stroke set by displacement, whatever the speed. When the first effect outside
// the friction-law replacements is a time_delay of more than kLongDelaySamples sample periods, or hysteresis, the other
// hypothesis (hysteresis on its default elements; the delay that fits best on a log grid) is refit with the base on the
// moving samples split at their median speed, and each one's share of the base-refit residual on the slow and on the
// fast half is reported. When the other one explains at least as much on both halves (within
// options.position_time_margin), the record cannot tell them apart: the other is added to the effect's `alike` and its
// description says so. Notes say which evidence decided. Throws nothing.
void CheckDelayAgainstHysteresis(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                 const Eigen::MatrixXd& base, const DiagnosisOptions& options,
                                 DiagnosisResult* result);

}  // namespace mb::diagnosis_detail
