#pragma once
// The candidates' regressor matrix of the diagnosis (candidate_matrix.cc): every proposed effect's regressor columns
// beside the base's, scaled to unit RMS, less those the base already spans (DiagnoseMissingEffects, step 2).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/effect_catalogue.h"

namespace mb {
struct EffectType;  // models/diagnosis/effect_registry.h
}  // namespace mb

namespace mb::diagnosis_detail {

// A candidate effect, its regressor columns and their place in the full regressor matrix.
struct Candidate {
  EffectInstance effect;
  const EffectType* type = nullptr;
  EffectRegressors reg;
  std::vector<Eigen::Index> idx;
};

// The full regressor matrix [base, candidates' columns] (N × total), each column scaled to unit RMS by `scale`.
struct RegressorMatrix {
  std::vector<Candidate> cands;
  Eigen::MatrixXd x;
  Eigen::VectorXd scale;
  // The rows weighted by √w (Huber weights): what the Grams, held-out errors and significance test see.
  Eigen::MatrixXd wx;
  Eigen::VectorXd wr;
  void Weigh(const Eigen::VectorXd& r, const Eigen::VectorXd& w) {
    const Eigen::VectorXd sw = w.cwiseSqrt();
    wx = sw.asDiagonal() * x;
    wr = sw.cwiseProduct(r);
  }
};

// Parallel filtering of a candidate's columns (DiagnosisOptions::regressor_filter_hz). Regressors built from the model
// output alone are in the filtered band already. (quantization is built from it too, but its rounding puts energy above
// the cut-off that the measured, filtered output lost.)
void FilterCandidateColumns(const EffectType& type, const DiagnosisSignals& signals, const DiagnosisOptions& options,
                            Eigen::MatrixXd* columns);

// 2. The candidates' regressors (each effect's EffectType::regressors on `signals`, filtered as above) beside the base's
// columns; those the base already spans (DiagnosisOptions::redundant_with_base) are not candidates, and those whose
// regressors cannot be computed on this record are skipped (a note each).
RegressorMatrix BuildCandidateMatrix(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                                     const std::vector<EffectInstance>& proposed, const DiagnosisOptions& options,
                                     std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail
