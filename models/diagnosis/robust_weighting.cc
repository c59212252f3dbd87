// Robust weighting (DiagnoseMissingEffects, every fit of the ranking): Huber weights w = min(1, k·σ/|e|) with the
// scale σ = 1.4826·MAD, found by iteratively reweighted least squares. Source: DIAGNOSIS.md, "When the base model is
// wrong elsewhere" (a robust loss by IRLS); Huber, "Robust estimation of a location parameter" (1964) and Robust
// Statistics (1981); the MAD's factor 1.4826 makes it consistent for Gaussian noise.
#include "models/diagnosis/robust_weighting.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>
#include <tbb/parallel_for.h>

namespace mb::diagnosis_detail {

double RobustScale(const Eigen::VectorXd& e) {
  if (e.size() == 0) return 0.0;
  const std::vector<double> values(e.data(), e.data() + e.size());
  const double median = Percentile(values, 0.5);
  std::vector<double> deviation(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) deviation[i] = std::abs(values[i] - median);
  return 1.4826 * Percentile(deviation, 0.5);
}

namespace {

// Huber weights of a residual: w = min(1, k·σ/|e|), σ = RobustScale(e) (all 1 when k <= 0 or σ = 0).
Eigen::VectorXd HuberWeights(const Eigen::VectorXd& e, double k) {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(e.size());
  if (!(k > 0.0)) return w;
  const double sigma = RobustScale(e);
  if (!(sigma > 0.0)) return w;
  for (Eigen::Index i = 0; i < e.size(); ++i) {
    const double a = std::abs(e(i));
    if (a > k * sigma) w(i) = k * sigma / a;
  }
  return w;
}

// r − xθ with θ minimising ‖√w ⊙ (r − xθ)‖: a tall-skinny QR. Columns that depend on others exactly are dropped only
// where round-off leaves their pivot under ColPivHouseholderQR's default threshold (ε·q of the largest), as in the
// dense QR this replaced; above it the residual carries that pivot's round-off.
// Each block of kBlockRows rows of [√w ⊙ x, √w ⊙ r] is reduced to its triangle by a blocked Householder QR (in
// parallel, in cache), the triangles stacked in block order and solved by ColPivHouseholderQR — the pivoted QR of the
// whole N × q matrix to round-off (the stack has its Gram matrix), without an N × q copy or N-long reflector sweeps.
// Source: Demmel, Grigori, Hoemmen, Langou, "Communication-optimal parallel and sequential QR and LU
// factorizations", SIAM J. Sci. Comput. 34 (2012) (TSQR).
Eigen::VectorXd WeightedFitResidual(const Eigen::MatrixXd& x, const Eigen::VectorXd& r, const Eigen::VectorXd& sw) {
  constexpr Eigen::Index kBlockRows = 8192;
  const Eigen::Index n = x.rows(), q = x.cols(), blocks = (n + kBlockRows - 1) / kBlockRows;
  std::vector<Eigen::MatrixXd> triangles(static_cast<std::size_t>(blocks));
  tbb::parallel_for(Eigen::Index{0}, blocks, [&](Eigen::Index b) {
    const Eigen::Index begin = b * kBlockRows, rows = std::min(kBlockRows, n - begin);
    Eigen::MatrixXd a(rows, q + 1);
    a.leftCols(q) = sw.segment(begin, rows).asDiagonal() * x.middleRows(begin, rows);
    a.col(q) = sw.segment(begin, rows).cwiseProduct(r.segment(begin, rows));
    const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(a);
    const Eigen::Index kept = std::min(rows, q + 1);
    triangles[static_cast<std::size_t>(b)] = a.topRows(kept).triangularView<Eigen::Upper>();
  });
  Eigen::Index stacked_rows = 0;
  for (const auto& t : triangles) stacked_rows += t.rows();
  Eigen::MatrixXd stacked(stacked_rows, q + 1);
  Eigen::Index row = 0;
  for (const auto& t : triangles) {
    stacked.middleRows(row, t.rows()) = t;
    row += t.rows();
  }
  const Eigen::VectorXd theta = stacked.leftCols(q).colPivHouseholderQr().solve(stacked.col(q));
  return r - x * theta;
}

}  // namespace

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

Eigen::VectorXd RobustWeights(const Eigen::MatrixXd& x, const Eigen::VectorXd& r, double k, Eigen::VectorXd* residual) {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(r.size());
  *residual = r;
  for (int iteration = 0; iteration < 10; ++iteration) {
    if (x.cols() > 0) {
      *residual = WeightedFitResidual(x, r, w.cwiseSqrt());
    }
    if (!(k > 0.0)) break;
    const Eigen::VectorXd next = HuberWeights(*residual, k);
    const double change = (next - w).cwiseAbs().maxCoeff();
    w = next;
    if (change < 1e-3) break;
  }
  return w;
}

}  // namespace mb::diagnosis_detail
