#pragma once
// Contiguous-block cross-validation of the diagnosis' least-squares fits (cross_validation.cc): per-block Gram
// matrices, so that the held-out error of any subset of the regressor columns costs O(p³) (DIAGNOSIS.md, step 3).

#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/candidate_matrix.h"

namespace mb::diagnosis_detail {

// Per-block Gram matrices of the scaled regressor matrix, for fast contiguous-block cross-validation.
class BlockGrams {
 public:
  // The weighted regressor matrix of `m` (its columns scaled to unit RMS, times √w: N × m.cols()) and the weighted
  // residual m.wr (N) split into `folds` contiguous blocks; each block's Gram is accumulated over row chunks
  // (RegressorMatrix::WeightedRows), so no N × q matrix is formed. m must have been weighed (RegressorMatrix::Weigh).
  BlockGrams(const RegressorMatrix& m, Eigen::Index folds);

  // The same Grams, their entries computed when a query first needs them (the ranking's matrix of the whole grammar:
  // q of several hundred columns, whose N·q²/2 products took a fifth of compare on the grammar's draws, of which the
  // forward selection reads the columns of the effects chosen against all, and each candidate's own block). Now: the
  // moments, each candidate's (and the base's) own block, and the base's columns against all; a query holding two
  // columns of different candidates, neither computed yet, computes the first one's against all (O(N·q)). `m` must
  // stay where it is and unchanged while the Grams read it: until Detach (KeepChosenOnly restricts them first). The
  // entries are the eager constructor's up to rounding (another order of summation). Queries fill entries in const
  // calls: not for use from two threads at once.
  struct Lazy {};
  BlockGrams(const RegressorMatrix& m, Eigen::Index folds, Lazy);

  // Forgets the matrix the lazy Grams read; a query that needs an entry not yet computed throws std::logic_error from
  // then on. No effect on eager Grams.
  void Detach() { source_ = nullptr; }

  // The held-out residuals √w⊙r_b − √w⊙X_b(idx)·θ_{−b} of every block (N), for the rows of `m` (the one the Grams
  // were built from).
  Eigen::VectorXd HeldOutErrors(const std::vector<Eigen::Index>& idx, const RegressorMatrix& m) const;

  // Held-out mean squared error of the least-squares fit on the columns `idx`.
  double HeldOutMse(const std::vector<Eigen::Index>& idx) const;

  // In-sample fit on all data: coefficients (scaled columns) and the residual sum of squares.
  Eigen::VectorXd Fit(const std::vector<Eigen::Index>& idx, double* sse) const;

  // The in-sample residuals √w⊙r − √w⊙X(idx)·θ of that fit (N), for the rows of `m` (the one the Grams were built
  // from): what a comparison of two equally large fits by their likelihood reads (Vuong's test).
  Eigen::VectorXd InSampleErrors(const std::vector<Eigen::Index>& idx, const RegressorMatrix& m) const;

  // The Grams of the columns `idx` alone, column k of the result being idx[k]: the same entries, exactly.
  BlockGrams Restrict(const std::vector<Eigen::Index>& idx) const;

  Eigen::MatrixXd TotalGram(const std::vector<Eigen::Index>& idx) const {
    Ensure(idx);
    return SubMatrix(total_gram_, idx);
  }
  double n() const { return n_; }

 private:
  BlockGrams() = default;
  static Eigen::MatrixXd SubMatrix(const Eigen::MatrixXd& m, const std::vector<Eigen::Index>& idx);
  static Eigen::VectorXd SubVector(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& idx);
  // Columns have unit RMS, so a ridge of 1e-9·(mean diagonal) only matters for collinear columns.
  static Eigen::VectorXd Solve(Eigen::MatrixXd g, const Eigen::VectorXd& h);
  // The fit on every block but b: each column's ridge kHeldOutRidge × its energy over the whole record. A column that
  // lives in block b alone (in simulation mode the loop's response to a constant force under integral action is a
  // transient at the start) has almost no energy elsewhere; unpenalised, its coefficient fitted on the other blocks is
  // noise over nearly nothing, and its held-out prediction in block b explodes. A column spread over the record loses
  // kHeldOutRidge / (its share outside b) of its coefficient: 1.3e-4 for a fifth held out.
  Eigen::VectorXd SolveHeldOut(const std::vector<Eigen::Index>& idx, std::size_t b) const;
  static constexpr double kHeldOutRidge = 1e-4;

  // Lazy Grams: computes every entry (i, j), i and j in idx, not yet computed (the columns' against all, one at a time).
  void Ensure(const std::vector<Eigen::Index>& idx) const;
  bool Known(Eigen::Index i, Eigen::Index j) const {
    const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
    return filled_.empty() || filled_[ui] || filled_[uj] || group_[ui] == group_[uj];
  }
  void FillColumn(Eigen::Index k) const;

  // Lazy Grams fill these in const queries (Ensure).
  mutable std::vector<Eigen::MatrixXd> gram_;
  std::vector<Eigen::VectorXd> xty_;
  std::vector<double> yty_;
  mutable Eigen::MatrixXd total_gram_;
  // Lazy Grams: per column, whether its entries against every column are computed (empty: eager, all are), and its
  // group (0 the base, c + 1 candidate c: a group's own block is computed at construction); the matrix read.
  mutable std::vector<char> filled_;
  std::vector<Eigen::Index> group_;
  const RegressorMatrix* source_ = nullptr;
  Eigen::VectorXd total_xty_;
  double total_yty_ = 0.0;
  double n_ = 0.0;
  Eigen::Index folds_ = 0;
};

}  // namespace mb::diagnosis_detail
