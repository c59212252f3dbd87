// The real-time path allocates nothing: a counting global operator new around the predict calls.
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "models/gpr/gpr_fit.h"
#include "tests/gpr/synthetic_data.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace mb {
namespace {

TEST(GprRealTime, PredictAllocatesNothing) {
  const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 31);
  for (GprKernel kernel : {GprKernel::kPeriodicSe, GprKernel::kSeSe}) {
    GprFitOptions options;
    options.kernel = kernel;
    options.restarts = 0;
    const GprModel model = FitGpr(data.x, data.xdot, data.d, options);
    const long before_check = g_allocations.load();
    auto* probe = new int(1);  // the counter works
    delete probe;
    ASSERT_EQ(g_allocations.load(), before_check + 1);

    const long before = g_allocations.load();
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
    EXPECT_EQ(g_allocations.load(), before) << GprKernelName(kernel);
    EXPECT_TRUE(std::isfinite(sum));
  }
}

}  // namespace
}  // namespace mb
