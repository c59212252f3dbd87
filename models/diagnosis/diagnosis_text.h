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

}  // namespace mb::diagnosis_detail
