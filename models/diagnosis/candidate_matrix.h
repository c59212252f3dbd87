#pragma once
// The candidates' regressor matrix of the diagnosis (candidate_matrix.cc): every proposed effect's regressor columns
// beside the base's, scaled to unit RMS, less those the base already spans (DiagnoseMissingEffects, step 2).

#include <cstddef>
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

// The full regressor matrix [base, candidates' columns] (N × cols()), each column scaled to unit RMS by `scale`. It is
// held as the base's columns and each candidate's own (Candidate::reg.columns, in their own units), not copied into
// one N × cols() matrix, nor weighted into another: column j is Raw(j)/scale(j), and the Grams read the rows weighted
// a block at a time (WeightedRows). On a record of 10⁶ samples and ≈ 100 columns each copy would be 0.8 GB.
struct RegressorMatrix {
  std::vector<Candidate> cands;
  Eigen::MatrixXd base;   // N × p: the base's regressors, in their own units
  Eigen::VectorXd scale;  // cols(): each column's RMS (1 where it is 0)
  // √w of the Huber weights and √w ⊙ r (N each, Weigh): what the Grams, held-out errors and significance test see.
  Eigen::VectorXd sw;
  Eigen::VectorXd wr;

  Eigen::Index rows() const { return base.rows(); }
  Eigen::Index cols() const { return scale.size(); }
  // Column j (0 ≤ j < cols()) in its own units: the base's, or a candidate's (N).
  Eigen::MatrixXd::ConstColXpr Raw(Eigen::Index j) const;
  // Column j scaled to unit RMS (N).
  auto Col(Eigen::Index j) const { return Raw(j) / scale(j); }
  // Rows [start, start + count) of every scaled column weighted by √w, into `chunk` (resized to count × cols()).
  void WeightedRows(Eigen::Index start, Eigen::Index count, Eigen::MatrixXd* chunk) const;
  void Weigh(const Eigen::VectorXd& r, const Eigen::VectorXd& w) {
    sw = w.cwiseSqrt();
    wr = sw.cwiseProduct(r);
  }
  // Records which candidate holds each column beyond the base's (BuildCandidateMatrix, after `cands` is final).
  void IndexColumns();

 private:
  std::vector<std::size_t> owner_;  // cols() − p: the candidate of column p + i
};

// Parallel filtering of a candidate's columns (DiagnosisOptions::regressor_filter_hz), or in simulation mode the
// candidate's force through the closed loop (CatalogueOptions::loop). Regressors built from the model output alone
// are in the filtered band, and in the output's space, already. (quantization is built from it too, but its rounding puts energy above
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
