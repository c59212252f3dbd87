// RobustWeights' weighted fit (models/diagnosis/robust_weighting.cc) is a tall-skinny QR over blocks of 8,192 rows:
// checked against the dense pivoted QR of the whole matrix, across block boundaries and with a last block shorter
// than the column count.

#include "models/diagnosis/robust_weighting.h"

#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace mb::diagnosis_detail {
namespace {

struct Regression {
  Eigen::MatrixXd x;
  Eigen::VectorXd r;
};

// N rows of q smooth and random columns, r a combination of them plus noise and a few gross outliers.
Regression MakeRegression(Eigen::Index n, Eigen::Index q, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Regression g{Eigen::MatrixXd(n, q), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n);
    for (Eigen::Index j = 0; j < q; ++j) g.x(i, j) = j % 2 == 0 ? std::sin(3.0 * static_cast<double>(j + 1) * t) : normal(rng);
    g.r(i) = 0.1 * normal(rng) + (i % 997 == 0 ? 25.0 : 0.0);
  }
  g.r += g.x * Eigen::VectorXd::LinSpaced(q, 1.0, 2.0);
  return g;
}

Eigen::VectorXd DenseResidual(const Eigen::MatrixXd& x, const Eigen::VectorXd& r) {
  return r - x * x.colPivHouseholderQr().solve(r);
}

TEST(RobustWeightsTest, UnweightedFitEqualsTheDensePivotedQrAcrossBlocks) {
  // 20,003 rows: two full blocks and a partial one; 8,195 rows: a last block of 3 rows for 6 columns.
  for (const Eigen::Index n : {Eigen::Index{20003}, Eigen::Index{8195}, Eigen::Index{500}}) {
    const Regression g = MakeRegression(n, 6, 7u);
    Eigen::VectorXd residual;
    const Eigen::VectorXd w = RobustWeights(g.x, g.r, 0.0, &residual);
    EXPECT_EQ(w, Eigen::VectorXd::Ones(n)) << n;
    const Eigen::VectorXd dense = DenseResidual(g.x, g.r);
    EXPECT_LT((residual - dense).cwiseAbs().maxCoeff(), 1e-10 * dense.cwiseAbs().maxCoeff()) << n << " rows";
  }
}

TEST(RobustWeightsTest, HuberWeightsDownweightTheOutliersAndTheFitIgnoresThem) {
  const Regression g = MakeRegression(20003, 4, 5u);
  Eigen::VectorXd residual;
  const Eigen::VectorXd w = RobustWeights(g.x, g.r, 1.345, &residual);
  EXPECT_LT(w(997), 0.1);  // a 25-unit outlier against noise of 0.1
  // Most ordinary samples keep their full weight (|e| ≤ 1.345σ: 82 % of a normal sample).
  Eigen::Index full = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) full += i % 997 != 0 && w(i) == 1.0 ? 1 : 0;
  EXPECT_GT(static_cast<double>(full) / static_cast<double>(w.size()), 0.75);
  // The outliers barely move the fit: the residual at ordinary samples is the noise, not the outliers' pull.
  Eigen::Index ordinary = 0;
  double sum_squares = 0.0;
  for (Eigen::Index i = 0; i < residual.size(); ++i) {
    if (i % 997 == 0) continue;
    sum_squares += residual(i) * residual(i);
    ++ordinary;
  }
  EXPECT_NEAR(std::sqrt(sum_squares / static_cast<double>(ordinary)), 0.1, 0.005);
}

}  // namespace
}  // namespace mb::diagnosis_detail
