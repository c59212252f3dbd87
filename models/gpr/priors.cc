#include "models/gpr/priors.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mb {

GprPriors DefaultGprPriors(GprKernel kernel, double period, GprRange x_range, GprRange xdot_range,
                           double target_variance) {
  const double range_x = x_range.max - x_range.min;
  const double range_v = xdot_range.max - xdot_range.min;
  const auto require = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string("DefaultGprPriors: ") + what +
                                  " must be finite and > 0, got " + std::to_string(v));
    }
  };
  require(target_variance, "the variance of the centred targets");
  require(range_x, "the trained position range (max x − min x)");
  require(range_v, "the trained velocity range (max xdot − min xdot)");
  require(period, "the period");
  const double s2 = target_variance;
  const double decade = std::log(10.0);
  GprPriors p;
  p[kLogSignalVarianceX] = {0.5 * s2, decade, 1e-6 * s2, 1e2 * s2};
  p[kLogSignalVarianceXdot] = {0.5 * s2, decade, 1e-6 * s2, 1e2 * s2};
  p[kLogNoiseVariance] = {0.05 * s2, decade, 1e-5 * s2, 2.0 * s2};
  p[kLogLengthScaleX] = kernel == GprKernel::kPeriodicSe
                            ? GprParameterPrior{1.0, 1.0, 0.15, 20.0}
                            : GprParameterPrior{period / 4.0, 1.0, period / 10.0,
                                                std::max(range_x, period)};
  p[kLogLengthScaleXdot] = {range_v / 3.0, 0.5, range_v / 10.0, 5.0 * range_v};
  p[kLogPeriod] = {period, 0.02, 0.9 * period, 1.1 * period};
  return p;
}

double GprLogPrior(const GprPriors& priors, const Eigen::Ref<const Eigen::VectorXd>& theta,
                   const std::array<bool, kGprParameterCount>& free, Eigen::VectorXd* gradient) {
  double value = 0.0;
  for (int i = 0; i < kGprParameterCount; ++i) {
    const auto& prior = priors[static_cast<std::size_t>(i)];
    if (!free[static_cast<std::size_t>(i)] || !std::isfinite(prior.log_sd)) continue;
    const double z = (theta(i) - std::log(prior.median)) / prior.log_sd;
    value -= 0.5 * z * z;
    if (gradient != nullptr) (*gradient)(i) -= z / prior.log_sd;
  }
  return value;
}

void ValidateGprPriors(const GprPriors& priors) {
  for (int i = 0; i < kGprParameterCount; ++i) {
    const auto& p = priors[static_cast<std::size_t>(i)];
    const std::string where = "priors." + std::string(GprParameterName(i)) + ": ";
    if (!(p.lower > 0.0) || !std::isfinite(p.lower)) {
      throw std::invalid_argument(where + "lower bound must be finite and > 0, got " +
                                  std::to_string(p.lower));
    }
    if (!(p.upper >= p.lower)) {
      throw std::invalid_argument(where + "upper bound " + std::to_string(p.upper) +
                                  " is below the lower bound " + std::to_string(p.lower));
    }
    if (!std::isfinite(p.median) || p.median < p.lower || p.median > p.upper) {
      throw std::invalid_argument(where + "median " + std::to_string(p.median) +
                                  " must lie within [lower, upper]");
    }
    if (!(p.log_sd > 0.0)) {
      throw std::invalid_argument(where + "log_sd must be > 0 (use infinity for a flat prior), got " +
                                  std::to_string(p.log_sd));
    }
  }
}

}  // namespace mb
