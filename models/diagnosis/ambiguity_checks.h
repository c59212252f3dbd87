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

// 6b. Hysteresis: does the residual loop against position — the way out differing from the way back by more than
// a constant (which is Coulomb friction)? Per position bin (20), the mean residual moving forward minus moving back;
// a note when that difference varies over the travel well beyond its sampling error (ratio > 10: the samples are
// autocorrelated) and by more than 10 % of the residual's RMS.
void NoteHysteresis(const DiagnosisSignals& signals, const Eigen::VectorXd& residual, DiagnosisResult* result);

}  // namespace mb::diagnosis_detail
