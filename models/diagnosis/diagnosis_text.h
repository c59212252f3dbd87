#pragma once
// The diagnosis in words (diagnosis_text.cc): each chosen effect described with its parameters in the position's unit,
// and the summary paragraph with its supporting evidence (DiagnoseMissingEffects, steps 5 and 7).

#include <string>

#include <Eigen/Core>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/diagnosis.h"

namespace mb::diagnosis_detail {

// 5. One chosen effect in words: its share, parameters (periodic ones also their first harmonic's amplitude),
// coefficients, and where its fitted contribution is largest.
DiagnosedEffect DescribeEffect(const Candidate& c, double score, double cumulative, const Eigen::VectorXd& coefficients,
                               const Eigen::VectorXd& coefficient_std, const DiagnosisSignals& signals,
                               const std::string& position_unit, bool friction_law);

// 7. Evidence (whiteness, the strongest position-periodogram peak) and the summary for users.
void Summarise(const DiagnosisOptions& options, const std::string& ambiguity_note, DiagnosisResult* result);

// Simulation mode (result->loop set): what the position can show. A periodic force of amplitude A at f moves the output
// by A·|H(f)| (LoopResponse::GainAt); against the residual's own level near f (`residual`, N samples at
// `sample_period`: Welch's density S(f)), its peak in the record's periodogram stands 10 × above that level when
// A ≥ √(20·S(f)/T)/|H(f)|, T the record's length. A note gives that smallest force at frequencies 1, 2, 5, 10, … Hz
// below half the Nyquist frequency: a force the equation-error view names below it is one the position cannot show.
void NoteWhatThePositionShows(const Eigen::VectorXd& residual, double sample_period, const std::string& unit,
                              DiagnosisResult* result);

}  // namespace mb::diagnosis_detail
