// The real-time path allocates nothing: a counting global operator new around the predict calls.

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace mb
