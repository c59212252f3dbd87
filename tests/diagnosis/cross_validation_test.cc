// Contiguous-block cross-validation (models/diagnosis/cross_validation.h): the lazy Grams give the eager Grams' fits.
#include "models/diagnosis/cross_validation.h"

#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace mb::diagnosis_detail {
namespace {

// A base of 2 columns and candidates of 1, 2 and 1 columns over 600 samples, Huber-like weights, and a residual that
// the base and the second candidate explain, with noise.
RegressorMatrix Matrix() {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Index n = 600;
  const auto random = [&](Eigen::Index cols) {
    Eigen::MatrixXd x(n, cols);
    for (Eigen::Index j = 0; j < cols; ++j)
      for (Eigen::Index i = 0; i < n; ++i) x(i, j) = normal(rng) + 0.3 * static_cast<double>(j + 1);
    return x;
  };
  RegressorMatrix m;
  m.base = random(2);
  Eigen::Index col = 2;
  for (Eigen::Index k : {1, 2, 1}) {
    Candidate c;
    c.reg.columns = random(k) * static_cast<double>(col);  // each in its own units
    for (Eigen::Index j = 0; j < k; ++j) c.idx.push_back(col++);
    m.cands.push_back(std::move(c));
  }
  m.scale.resize(col);
  m.IndexColumns();
  for (Eigen::Index j = 0; j < col; ++j) m.scale(j) = std::sqrt(m.Raw(j).squaredNorm() / static_cast<double>(n));
  Eigen::VectorXd r = m.base.col(0) - 0.5 * m.cands[1].reg.columns.col(1) + 0.1 * random(1).col(0);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  for (Eigen::Index i = 0; i < n; i += 7) w(i) = 0.4;
  m.Weigh(r, w);
  return m;
}

TEST(BlockGrams, LazyGramsGiveTheEagerFitsAndSayWhatTheyNeverComputed) {
  const RegressorMatrix m = Matrix();
  const BlockGrams eager(m, 5);
  BlockGrams lazy(m, 5, BlockGrams::Lazy{});
  const std::vector<std::vector<Eigen::Index>> sets = {{0, 1, 2}, {0, 1, 3, 4}, {0, 1, 2, 5}, {0, 1, 2, 3, 4}, {}};
  for (const std::vector<Eigen::Index>& idx : sets) {
    EXPECT_NEAR(lazy.HeldOutMse(idx), eager.HeldOutMse(idx), 1e-12 * eager.HeldOutMse(idx));
    double sse_lazy = 0.0, sse_eager = 0.0;
    const Eigen::VectorXd theta = lazy.Fit(idx, &sse_lazy);
    EXPECT_LT((theta - eager.Fit(idx, &sse_eager)).norm(), 1e-10) << idx.size() << " columns";
    EXPECT_NEAR(sse_lazy, sse_eager, 1e-12 * sse_eager);
    EXPECT_LT((lazy.HeldOutErrors(idx, m) - eager.HeldOutErrors(idx, m)).norm(), 1e-10);
  }
  // The second candidate's fit explains the residual: the held-out error falls well below the base's.
  EXPECT_LT(lazy.HeldOutMse({0, 1, 3, 4}), 0.1 * lazy.HeldOutMse({0, 1}));
  const BlockGrams restricted = lazy.Restrict({0, 1, 3, 4});
  EXPECT_NEAR(restricted.HeldOutMse({0, 1, 2, 3}), eager.HeldOutMse({0, 1, 3, 4}), 1e-12);
  // Detached, the entries computed stay (column 2's against all, since {0, 1, 2, 5}); one never computed (columns 3
  // and 5, of the second and third candidates, were never in one query) is an error, not a wrong number.
  lazy.Detach();
  EXPECT_NO_THROW(lazy.HeldOutMse({0, 1, 2, 5}));
  EXPECT_THROW(lazy.HeldOutMse({0, 1, 3, 5}), std::logic_error);
}

}  // namespace
}  // namespace mb::diagnosis_detail
