// The real-time path allocates nothing: a counting global operator new around the predict calls.

#include <gtest/gtest.h>

#include "models/gpr/feature_map.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_recursive.h"
#include "tests/alloc_counter.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

TEST(GprRealTime, PredictAllocatesNothing) {
  const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 31);
  for (GprKernel kernel : {GprKernel::kPeriodicSe, GprKernel::kSeSe}) {
    GprFitOptions options;
    options.kernel = kernel;
    options.restarts = 0;
    const GprModel model = FitGpr(data.x, data.xdot, data.d, options);
    const long before_check = ::mb::testing::AllocationCount();
    void* probe = ::operator new(16);  // the counter works
    const long after_check = ::mb::testing::AllocationCount();
    ::operator delete(probe);
    ASSERT_EQ(after_check, before_check + 1);

    const long before = ::mb::testing::AllocationCount();
    double sum = 0.0;
    for (int i = 0; i < 1000; ++i) {
      const double x = -0.5 + 0.0017 * i, v = -0.1 + 0.0008 * i;
      sum += model.PredictPosteriorMean(x, v);
      double mean = 0.0, std = 0.0;
      model.Predict(x, v, &mean, &std);
      sum += model.PredictConfidenceWeightedMean(model.fitted_posterior(), x, v);
      double gx = 0.0, gv = 0.0;
      model.PosteriorMeanGradient(x, v, &gx, &gv);
      sum += mean + std + gx + gv;
    }
    EXPECT_EQ(::mb::testing::AllocationCount(), before) << GprKernelName(kernel);
    EXPECT_TRUE(std::isfinite(sum));

    // Learning online (gpr_recursive.h): the rank-one update and its prediction allocate nothing either.
    GprRecursivePosterior online(model, 0.999);
    const long before_online = ::mb::testing::AllocationCount();
    for (int i = 0; i < 200; ++i) {
      const double x = 0.1 + 0.001 * i, v = 0.05 + 0.002 * i;
      online.Update(x, v, 0.3);
      sum += online.PredictPosteriorMean(x, v);
    }
    EXPECT_EQ(::mb::testing::AllocationCount(), before_online) << GprKernelName(kernel) << " online";
    EXPECT_TRUE(std::isfinite(sum));
  }
}

// The widest feature map (feature_map.h) at the largest basis a model may have: the quadratic form's scratch is
// the caller's stack buffer and the vector kernels allocate nothing either.
TEST(GprRealTime, FeatureMapAllocatesNothingAtTheLargestBasis) {
  GprBasis basis;
  basis.kernel = GprKernel::kSeSe;
  basis.x_domain = {0.2, 0.3, kMaxGprFeatures / 2};
  basis.xdot_domain = {0.25, 0.4, kMaxGprFeatures / 2};
  const GprFeatureMap map(basis);
  ASSERT_EQ(map.feature_count(), kMaxGprFeatures);
  const Eigen::VectorXd beta = Eigen::VectorXd::Constant(kMaxGprFeatures, 0.5);
  const Eigen::MatrixXd cov = Eigen::MatrixXd::Identity(kMaxGprFeatures, kMaxGprFeatures);
  const GprPackedLowerTriangle packed(cov);
  GprFeatureBuffer psi;
  const long before = ::mb::testing::AllocationCount();
  double sum = 0.0;
  for (int i = 0; i < 20; ++i) {
    sum += map.EvaluateAndDot(beta.data(), 0.1 + 0.01 * i, 0.3, psi.values);
    sum += map.QuadraticForm(cov.data(), psi.values) + map.WeightedSquares(beta.data(), psi.values);
    sum += map.QuadraticForm(packed, psi);
  }
  EXPECT_EQ(::mb::testing::AllocationCount(), before) << map.instruction_set();
  EXPECT_TRUE(std::isfinite(sum));
  // ψᵀIψ = |ψ|² = 2·WeightedSquares with s = 0.5: the kernels agree with each other at this size.
  EXPECT_NEAR(map.QuadraticForm(cov.data(), psi.values), 2.0 * map.WeightedSquares(beta.data(), psi.values),
              1e-12 * map.QuadraticForm(cov.data(), psi.values));
}

}  // namespace
}  // namespace mb
