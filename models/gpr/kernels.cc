#include "models/gpr/kernels.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mb {

std::string_view GprKernelName(GprKernel kernel) noexcept {
  return kernel == GprKernel::kPeriodicSe ? "PS" : "DS";
}

GprKernel ParseGprKernel(std::string_view name) {
  if (name == "PS") return GprKernel::kPeriodicSe;
  if (name == "DS") return GprKernel::kSeSe;
  throw std::invalid_argument("unknown GPR kernel \"" + std::string(name) +
                              "\": use \"PS\" (periodic(x) + SE(xdot), paper eq. 19) or \"DS\" "
                              "(SE(x) + SE(xdot), eq. 27)");
}

std::string_view GprParameterName(int parameter) noexcept {
  switch (parameter) {
    case kLogSignalVarianceX: return "signal_variance_x";
    case kLogLengthScaleX: return "length_scale_x";
    case kLogSignalVarianceXdot: return "signal_variance_xdot";
    case kLogLengthScaleXdot: return "length_scale_xdot";
    case kLogNoiseVariance: return "noise_variance";
    case kLogPeriod: return "period";
    default: return "unknown";
  }
}

double PeriodicKernel(double a, double b, double signal_variance, double length_scale,
                      double period) noexcept {
  const double s = std::sin(std::numbers::pi * std::abs(a - b) / period);
  return signal_variance * std::exp(-2.0 * s * s / (length_scale * length_scale));
}

double SquaredExponentialKernel(double a, double b, double signal_variance,
                                double length_scale) noexcept {
  const double r = a - b;
  return signal_variance * std::exp(-r * r / (2.0 * length_scale * length_scale));
}

double TisoKernel(GprKernel kernel, const GprHyperparameters& hp, double x1, double xdot1,
                  double x2, double xdot2) noexcept {
  const double kx =
      kernel == GprKernel::kPeriodicSe
          ? PeriodicKernel(x1, x2, hp.signal_variance_x, hp.length_scale_x, hp.period)
          : SquaredExponentialKernel(x1, x2, hp.signal_variance_x, hp.length_scale_x);
  return kx + SquaredExponentialKernel(xdot1, xdot2, hp.signal_variance_xdot,
                                       hp.length_scale_xdot);
}

std::array<double, kGprParameterCount> TisoKernelGradient(GprKernel kernel,
                                                          const GprHyperparameters& hp,
                                                          double x1, double xdot1, double x2,
                                                          double xdot2) noexcept {
  std::array<double, kGprParameterCount> g{};
  const double r = x1 - x2;
  if (kernel == GprKernel::kPeriodicSe) {
    const double l2 = hp.length_scale_x * hp.length_scale_x;
    const double phase = std::numbers::pi * r / hp.period;
    const double s = std::sin(phase);
    const double k = hp.signal_variance_x * std::exp(-2.0 * s * s / l2);
    g[kLogSignalVarianceX] = k;
    g[kLogLengthScaleX] = k * 4.0 * s * s / l2;
    // d/dlog τ of −2 sin²(πr/τ)/ℓ² = (2πr/(ℓ²τ)) sin(2πr/τ).
    g[kLogPeriod] = k * 2.0 * phase * std::sin(2.0 * phase) / l2;
  } else {
    const double l2 = hp.length_scale_x * hp.length_scale_x;
    const double k = hp.signal_variance_x * std::exp(-r * r / (2.0 * l2));
    g[kLogSignalVarianceX] = k;
    g[kLogLengthScaleX] = k * r * r / l2;
  }
  const double rv = xdot1 - xdot2;
  const double lv2 = hp.length_scale_xdot * hp.length_scale_xdot;
  const double kv = hp.signal_variance_xdot * std::exp(-rv * rv / (2.0 * lv2));
  g[kLogSignalVarianceXdot] = kv;
  g[kLogLengthScaleXdot] = kv * rv * rv / lv2;
  return g;
}

Eigen::MatrixXd TisoKernelMatrix(GprKernel kernel, const GprHyperparameters& hp,
                                 const Eigen::Ref<const Eigen::VectorXd>& x,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot) {
  if (x.size() != xdot.size()) {
    throw std::invalid_argument("TisoKernelMatrix: x has " + std::to_string(x.size()) +
                                " entries but xdot has " + std::to_string(xdot.size()));
  }
  const Eigen::Index n = x.size();
  Eigen::MatrixXd k(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j; i < n; ++i) {
      k(i, j) = TisoKernel(kernel, hp, x(i), xdot(i), x(j), xdot(j));
      k(j, i) = k(i, j);
    }
  }
  return k;
}

Eigen::MatrixXd TisoKernelMatrix(GprKernel kernel, const GprHyperparameters& hp,
                                 const Eigen::Ref<const Eigen::VectorXd>& x_a,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot_a,
                                 const Eigen::Ref<const Eigen::VectorXd>& x_b,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot_b) {
  if (x_a.size() != xdot_a.size() || x_b.size() != xdot_b.size()) {
    throw std::invalid_argument("TisoKernelMatrix: x and xdot must have equal lengths (got " +
                                std::to_string(x_a.size()) + "/" + std::to_string(xdot_a.size()) +
                                " and " + std::to_string(x_b.size()) + "/" +
                                std::to_string(xdot_b.size()) + ")");
  }
  Eigen::MatrixXd k(x_a.size(), x_b.size());
  for (Eigen::Index j = 0; j < x_b.size(); ++j) {
    for (Eigen::Index i = 0; i < x_a.size(); ++i) {
      k(i, j) = TisoKernel(kernel, hp, x_a(i), xdot_a(i), x_b(j), xdot_b(j));
    }
  }
  return k;
}

Eigen::VectorXd ToLogParameters(const GprHyperparameters& hp) {
  Eigen::VectorXd theta(kGprParameterCount);
  theta << std::log(hp.signal_variance_x), std::log(hp.length_scale_x),
      std::log(hp.signal_variance_xdot), std::log(hp.length_scale_xdot),
      std::log(hp.noise_variance), std::log(hp.period);
  return theta;
}

GprHyperparameters FromLogParameters(const Eigen::Ref<const Eigen::VectorXd>& theta) {
  if (theta.size() != kGprParameterCount) {
    throw std::invalid_argument("FromLogParameters: expected " +
                                std::to_string(kGprParameterCount) + " log-parameters, got " +
                                std::to_string(theta.size()));
  }
  GprHyperparameters hp;
  hp.signal_variance_x = std::exp(theta(kLogSignalVarianceX));
  hp.length_scale_x = std::exp(theta(kLogLengthScaleX));
  hp.signal_variance_xdot = std::exp(theta(kLogSignalVarianceXdot));
  hp.length_scale_xdot = std::exp(theta(kLogLengthScaleXdot));
  hp.noise_variance = std::exp(theta(kLogNoiseVariance));
  hp.period = std::exp(theta(kLogPeriod));
  return hp;
}

}  // namespace mb
