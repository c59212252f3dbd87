// Kernels eq. 19–21 / 27 against hand-written loops, and their gradients against finite
// differences.
#include "models/gpr/kernels.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mb {
namespace {

GprHyperparameters SomeHyperparameters() {
  GprHyperparameters hp;
  hp.signal_variance_x = 0.7;
  hp.length_scale_x = 0.8;
  hp.signal_variance_xdot = 0.4;
  hp.length_scale_xdot = 0.12;
  hp.noise_variance = 0.01;
  hp.period = 0.0225;
  return hp;
}

TEST(GprKernels, PeriodicMatchesEquation20) {
  const double tau = 0.0225;
  for (double a : {-0.3, 0.0, 0.011, 0.2}) {
    for (double b : {-0.1, 0.005, 0.0337, 0.5}) {
      const double s = std::sin(std::numbers::pi * std::abs(a - b) / tau);
      const double expected = 1.3 * std::exp(-2.0 * s * s / (0.6 * 0.6));
      EXPECT_NEAR(PeriodicKernel(a, b, 1.3, 0.6, tau), expected, 1e-15);
    }
  }
  // Periodic in the difference, maximal at whole periods, eq. 34.
  EXPECT_NEAR(PeriodicKernel(0.1, 0.1 + 7 * tau, 2.0, 0.5, tau), 2.0, 1e-12);
  EXPECT_NEAR(PeriodicKernel(0.1, 0.1 + 2.5 * tau, 2.0, 0.5, tau), 2.0 * std::exp(-8.0), 1e-12);
}

TEST(GprKernels, SquaredExponentialMatchesEquation21) {
  EXPECT_DOUBLE_EQ(SquaredExponentialKernel(0.3, 0.3, 0.9, 0.2), 0.9);
  EXPECT_NEAR(SquaredExponentialKernel(0.1, 0.4, 0.9, 0.2), 0.9 * std::exp(-0.09 / 0.08), 1e-15);
}

TEST(GprKernels, KernelMatrixMatchesHandWrittenLoop) {
  const GprHyperparameters hp = SomeHyperparameters();
  Eigen::VectorXd x(5), v(5);
  x << 0.0, 0.013, 0.041, 0.1, 0.33;
  v << 0.05, 0.1, 0.1, 0.35, 0.5;
  for (GprKernel kernel : {GprKernel::kPeriodicSe, GprKernel::kSeSe}) {
    const Eigen::MatrixXd k = TisoKernelMatrix(kernel, hp, x, v);
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) {
        const double dx = x(i) - x(j);
        const double dv = v(i) - v(j);
        const double s = std::sin(std::numbers::pi * std::abs(dx) / hp.period);
        const double kx = kernel == GprKernel::kPeriodicSe
                              ? hp.signal_variance_x *
                                    std::exp(-2.0 * s * s / (hp.length_scale_x * hp.length_scale_x))
                              : hp.signal_variance_x *
                                    std::exp(-dx * dx / (2.0 * hp.length_scale_x * hp.length_scale_x));
        const double kv = hp.signal_variance_xdot *
                          std::exp(-dv * dv / (2.0 * hp.length_scale_xdot * hp.length_scale_xdot));
        EXPECT_NEAR(k(i, j), kx + kv, 1e-14) << GprKernelName(kernel) << " at " << i << "," << j;
      }
    }
    const Eigen::MatrixXd cross = TisoKernelMatrix(kernel, hp, x, v, x.head(2), v.head(2));
    EXPECT_LT((cross - k.leftCols(2)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(GprKernels, GradientMatchesFiniteDifferences) {
  const GprHyperparameters hp = SomeHyperparameters();
  const Eigen::VectorXd theta = ToLogParameters(hp);
  const double h = 1e-6;
  for (GprKernel kernel : {GprKernel::kPeriodicSe, GprKernel::kSeSe}) {
    for (const auto& [x1, v1, x2, v2] : {std::array{0.01, 0.1, 0.047, 0.3},
                                         std::array{0.2, 0.5, 0.013, 0.05}}) {
      const auto g = TisoKernelGradient(kernel, hp, x1, v1, x2, v2);
      for (int p = 0; p < kGprParameterCount; ++p) {
        Eigen::VectorXd plus = theta, minus = theta;
        plus(p) += h;
        minus(p) -= h;
        const double fd = (TisoKernel(kernel, FromLogParameters(plus), x1, v1, x2, v2) -
                           TisoKernel(kernel, FromLogParameters(minus), x1, v1, x2, v2)) /
                          (2.0 * h);
        EXPECT_NEAR(g[static_cast<std::size_t>(p)], fd, 1e-8 * (1.0 + std::abs(fd)))
            << GprKernelName(kernel) << " d/d log " << GprParameterName(p);
      }
    }
  }
}

TEST(GprKernels, NamesParseAndRejectUnknown) {
  EXPECT_EQ(ParseGprKernel("PS"), GprKernel::kPeriodicSe);
  EXPECT_EQ(ParseGprKernel("DS"), GprKernel::kSeSe);
  EXPECT_EQ(GprKernelName(GprKernel::kSeSe), "DS");
  try {
    ParseGprKernel("ps");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "unknown GPR kernel \"ps\": use \"PS\" (periodic(x) + SE(xdot), paper eq. 19) or "
                 "\"DS\" (SE(x) + SE(xdot), eq. 27)");
  }
  EXPECT_THROW(TisoKernelMatrix(GprKernel::kSeSe, SomeHyperparameters(), Eigen::VectorXd(3),
                                Eigen::VectorXd(2)),
               std::invalid_argument);
}

}  // namespace
}  // namespace mb
