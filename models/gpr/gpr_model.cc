#include "models/gpr/gpr_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mb {
namespace {

void CheckPositive(std::vector<std::string>& errors, const char* name, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    errors.push_back(std::string(name) + " must be finite and > 0, got " + std::to_string(value));
  }
}

void CheckRange(std::vector<std::string>& errors, const char* name, GprRange r) {
  if (!std::isfinite(r.min) || !std::isfinite(r.max) || r.max < r.min) {
    errors.push_back(std::string(name) + " [" + std::to_string(r.min) + ", " +
                     std::to_string(r.max) + "] must be finite with min <= max");
  }
}

void CheckDomain(std::vector<std::string>& errors, const char* name, const HilbertDomain& d) {
  if (!std::isfinite(d.center) || !(d.half_width > 0.0) || !std::isfinite(d.half_width) ||
      d.count < 1) {
    errors.push_back(std::string(name) + " needs a finite center, half_width > 0 and count >= 1 "
                     "(got center " + std::to_string(d.center) + ", half_width " +
                     std::to_string(d.half_width) + ", count " + std::to_string(d.count) + ")");
  }
}

void ValidateModelData(const GprModelData& m) {
  std::vector<std::string> errors;
  const GprHyperparameters& hp = m.hyperparameters;
  CheckPositive(errors, "hyperparameters.signal_variance_x", hp.signal_variance_x);
  CheckPositive(errors, "hyperparameters.length_scale_x", hp.length_scale_x);
  CheckPositive(errors, "hyperparameters.signal_variance_xdot", hp.signal_variance_xdot);
  CheckPositive(errors, "hyperparameters.length_scale_xdot", hp.length_scale_xdot);
  CheckPositive(errors, "hyperparameters.noise_variance", hp.noise_variance);
  CheckPositive(errors, "hyperparameters.period", hp.period);
  if (!std::isfinite(m.mean)) errors.push_back("mean must be finite, got " + std::to_string(m.mean));
  CheckRange(errors, "trained_range.x", m.x_range);
  CheckRange(errors, "trained_range.xdot", m.xdot_range);
  if (m.basis.kernel != m.kernel) errors.push_back("basis kernel differs from the model kernel");
  if (m.kernel == GprKernel::kPeriodicSe) {
    if (m.basis.harmonics < 0) {
      errors.push_back("basis.harmonics must be >= 0, got " + std::to_string(m.basis.harmonics));
    }
    if (m.basis.period != hp.period) {
      errors.push_back("basis.period " + std::to_string(m.basis.period) +
                       " differs from hyperparameters.period " + std::to_string(hp.period));
    }
  } else {
    CheckDomain(errors, "basis.x_domain", m.basis.x_domain);
  }
  CheckDomain(errors, "basis.xdot_domain", m.basis.xdot_domain);
  if (errors.empty()) {
    const Eigen::Index features = GprFeatureCount(m.basis);
    if (features > kMaxGprFeatures) {
      errors.push_back("the basis has " + std::to_string(features) + " features, more than " +
                       std::to_string(kMaxGprFeatures));
    }
    if (m.weights.size() != features) {
      errors.push_back("weights has " + std::to_string(m.weights.size()) +
                       " entries but the basis has " + std::to_string(features) + " features");
    } else if (!m.weights.allFinite()) {
      errors.push_back("weights contains a non-finite value");
    }
    if (m.weight_covariance.rows() != features || m.weight_covariance.cols() != features) {
      errors.push_back("weight_covariance is " + std::to_string(m.weight_covariance.rows()) + "x" +
                       std::to_string(m.weight_covariance.cols()) + " but the basis has " +
                       std::to_string(features) + " features");
    } else if (!m.weight_covariance.allFinite()) {
      errors.push_back("weight_covariance contains a non-finite value");
    }
  }
  if (!errors.empty()) {
    std::string message = "invalid GPR model:";
    for (const auto& e : errors) message += "\n  " + e;
    throw std::invalid_argument(message);
  }
}

// max |Σ_k β_k ψ_k'| over n grid points of [a, b] plus (h/2)·curvature_bound.
template <typename DerivativeAt>
std::pair<double, double> LipschitzOnGrid(double a, double b, int n, double curvature_bound,
                                          DerivativeAt&& derivative_at) {
  double sampled = 0.0;
  const double h = n > 1 ? (b - a) / (n - 1) : 0.0;
  for (int i = 0; i < n; ++i) sampled = std::max(sampled, std::abs(derivative_at(a + i * h)));
  return {sampled, sampled + 0.5 * h * curvature_bound};
}

}  // namespace

GprModel::GprModel(GprModelData data) : data_(std::move(data)) {
  ValidateModelData(data_);
  GprSpectralWeights(data_.basis, data_.hyperparameters, &spectral_weights_);
  prior_variance_ = data_.hyperparameters.signal_variance_x + data_.hyperparameters.signal_variance_xdot;
  feature_map_ = GprFeatureMap(data_.basis);
  // The fitted covariance in the form its quadratic form reads fastest: cosine series for "DS", else packed.
  if (data_.kernel == GprKernel::kSeSe) {
    series_covariance_ = GprSeriesCovariance(feature_map_.constants(), data_.weight_covariance);
  } else {
    packed_covariance_ = GprPackedLowerTriangle(data_.weight_covariance);
  }
  packed_weights_ = GprPackedWeights(feature_map_.constants(), data_.weights.data());
}

double GprModel::ClampXdot(double xdot) const noexcept {
  return std::clamp(xdot, data_.xdot_range.min, data_.xdot_range.max);
}

double GprModel::PredictPosteriorMean(double x, double xdot) const noexcept {
  return PredictPosteriorMean(fitted_posterior(), x, xdot);
}

double GprModel::PredictPosteriorMean(const GprPosteriorView& posterior, double x, double xdot) const noexcept {
  if (!std::isfinite(x) || !std::isfinite(xdot)) return data_.mean;
  // The fitted β is read from its packed copy (aligned whole blocks; the same bits).
  return data_.mean + (posterior.weights == data_.weights.data()
                           ? feature_map_.Dot(packed_weights_, x, ClampXdot(xdot))
                           : feature_map_.Dot(posterior.weights, x, ClampXdot(xdot)));
}

void GprModel::Predict(double x, double xdot, double* mean, double* std) const noexcept {
  Predict(fitted_posterior(), x, xdot, mean, std);
}

void GprModel::Predict(const GprPosteriorView& posterior, double x, double xdot, double* mean,
                       double* std) const noexcept {
  if (!std::isfinite(x) || !std::isfinite(xdot)) {
    if (mean != nullptr) *mean = data_.mean;
    if (std != nullptr) *std = std::sqrt(prior_variance_);
    return;
  }
  if (std == nullptr) {
    if (mean != nullptr) *mean = PredictPosteriorMean(posterior, x, xdot);
    return;
  }
  GprFeatureBuffer psi;  // uninitialised scratch on the stack
  const double clamped_xdot = ClampXdot(xdot);
  const bool fitted_weights = posterior.weights == data_.weights.data();
  const double dot = fitted_weights ? feature_map_.EvaluateAndDot(packed_weights_, x, clamped_xdot, psi.values)
                                    : feature_map_.EvaluateAndDot(posterior.weights, x, clamped_xdot, psi.values);
  if (mean != nullptr) *mean = data_.mean + dot;  // the bits of PredictPosteriorMean
  // ψᵀΣψ from the lower triangle, and the prior variance carried by the basis, Σ s_k ψ_k². The fitted
  // posterior's covariance is read from its transformed copy (cosine series for "DS", else packed).
  double var = 0.0;
  if (posterior.covariance != data_.weight_covariance.data()) {
    var = feature_map_.QuadraticForm(posterior.covariance, psi.values);
  } else if (data_.kernel == GprKernel::kSeSe) {
    var = feature_map_.QuadraticForm(series_covariance_, x, clamped_xdot, psi);
  } else {
    var = feature_map_.QuadraticForm(packed_covariance_, psi);
  }
  const double represented_prior = feature_map_.WeightedSquares(spectral_weights_.data(), psi.values);
  const double missing_prior = std::max(prior_variance_ - represented_prior, 0.0);
  *std = std::sqrt(std::max(var, 0.0) + missing_prior);
}

void GprModel::PredictPosteriorMean(const Eigen::Ref<const Eigen::VectorXd>& x,
                                    const Eigen::Ref<const Eigen::VectorXd>& xdot,
                                    Eigen::Ref<Eigen::VectorXd> mean) const {
  if (x.size() != xdot.size() || x.size() != mean.size()) {
    throw std::invalid_argument("GprModel::PredictPosteriorMean: x, xdot and mean must have one "
                                "length (got " + std::to_string(x.size()) + ", " +
                                std::to_string(xdot.size()) + ", " + std::to_string(mean.size()) +
                                ")");
  }
  for (Eigen::Index i = 0; i < x.size(); ++i) mean(i) = PredictPosteriorMean(x(i), xdot(i));
}

void GprModel::Predict(const Eigen::Ref<const Eigen::VectorXd>& x,
                       const Eigen::Ref<const Eigen::VectorXd>& xdot,
                       Eigen::Ref<Eigen::VectorXd> mean, Eigen::Ref<Eigen::VectorXd> std) const {
  if (x.size() != xdot.size() || x.size() != mean.size() || x.size() != std.size()) {
    throw std::invalid_argument("GprModel::Predict: x, xdot, mean and std must have one length "
                                "(got " + std::to_string(x.size()) + ", " +
                                std::to_string(xdot.size()) + ", " + std::to_string(mean.size()) +
                                ", " + std::to_string(std.size()) + ")");
  }
  for (Eigen::Index i = 0; i < x.size(); ++i) Predict(x(i), xdot(i), &mean(i), &std(i));
}

void GprModel::PosteriorMeanGradient(double x, double xdot, double* dmu_dx,
                                     double* dmu_dxdot) const noexcept {
  std::array<double, kMaxGprFeatures> dx;
  std::array<double, kMaxGprFeatures> dv;
  const bool inside = xdot >= data_.xdot_range.min && xdot <= data_.xdot_range.max;
  EvaluateGprBasisDerivatives(data_.basis, x, ClampXdot(xdot), dx.data(), dv.data());
  double gx = 0.0;
  double gv = 0.0;
  for (Eigen::Index k = 0; k < data_.weights.size(); ++k) {
    gx += data_.weights(k) * dx[static_cast<std::size_t>(k)];
    gv += data_.weights(k) * dv[static_cast<std::size_t>(k)];
  }
  if (dmu_dx != nullptr) *dmu_dx = gx;
  if (dmu_dxdot != nullptr) *dmu_dxdot = inside ? gv : 0.0;
}

GprLipschitzConstants GprModel::LipschitzConstants(int grid_points) const {
  if (grid_points < 2) {
    throw std::invalid_argument("GprModel::LipschitzConstants: grid_points must be >= 2, got " +
                                std::to_string(grid_points));
  }
  const GprBasis& basis = data_.basis;
  const Eigen::Index m = GprFeatureCount(basis);
  const Eigen::Index p = GprPositionFeatureCount(basis);
  std::vector<double> frequency(static_cast<std::size_t>(m));
  GprBasisFrequencies(basis, frequency.data());
  // Bound on |μ''|: Σ |β_k| sup|ψ_k| ω_k².
  const auto curvature = [&](Eigen::Index from, Eigen::Index to, double sup_psi) {
    double c = 0.0;
    for (Eigen::Index k = from; k < to; ++k) {
      const double w = frequency[static_cast<std::size_t>(k)];
      c += std::abs(data_.weights(k)) * sup_psi * w * w;
    }
    return c;
  };
  GprLipschitzConstants out;
  const double mid_v = 0.5 * (data_.xdot_range.min + data_.xdot_range.max);
  const double mid_x = 0.5 * (data_.x_range.min + data_.x_range.max);
  double x_lo = 0.0;
  double x_hi = basis.period;
  double sup_x = 1.0;
  if (basis.kernel == GprKernel::kSeSe) {
    x_lo = basis.x_domain.center - basis.x_domain.half_width;
    x_hi = basis.x_domain.center + basis.x_domain.half_width;
    sup_x = 1.0 / std::sqrt(basis.x_domain.half_width);
  }
  const auto [px_sampled, px_bound] =
      LipschitzOnGrid(x_lo, x_hi, grid_points, curvature(0, p, sup_x), [&](double x) {
        double g = 0.0;
        PosteriorMeanGradient(x, mid_v, &g, nullptr);
        return g;
      });
  const double sup_v = 1.0 / std::sqrt(basis.xdot_domain.half_width);
  const auto [pv_sampled, pv_bound] = LipschitzOnGrid(
      data_.xdot_range.min, data_.xdot_range.max, grid_points, curvature(p, m, sup_v),
      [&](double v) {
        double g = 0.0;
        PosteriorMeanGradient(mid_x, v, nullptr, &g);
        return g;
      });
  out.position_sampled = px_sampled;
  out.position = px_bound;
  out.velocity_sampled = pv_sampled;
  out.velocity = pv_bound;
  return out;
}

double GprModel::ConfidenceWeight(double x, double xdot) const noexcept {
  double weight = 0.0;
  PredictConfidenceWeightedMean(x, xdot, &weight);
  return weight;
}

double GprModel::PredictConfidenceWeightedMean(double x, double xdot, double* weight) const noexcept {
  return PredictConfidenceWeightedMean(fitted_posterior(), x, xdot, weight);
}

double GprModel::PredictConfidenceWeightedMean(const GprPosteriorView& posterior, double x, double xdot,
                                               double* weight) const noexcept {
  double mean = 0.0;
  double std = 0.0;
  Predict(posterior, x, xdot, &mean, &std);
  const double g =
      std::isfinite(x) && std::isfinite(xdot) ? std::clamp(1.0 - std * std / prior_variance_, 0.0, 1.0) : 0.0;
  if (weight != nullptr) *weight = g;
  return g * mean;
}

GprLipschitzConstants GprModel::ConfidenceWeightedLipschitzConstants(int grid_points) const {
  if (grid_points < 16) {
    throw std::invalid_argument("GprModel::ConfidenceWeightedLipschitzConstants: grid_points must be >= 16, got " +
                                std::to_string(grid_points));
  }
  const GprBasis& basis = data_.basis;
  const bool periodic = basis.kernel == GprKernel::kPeriodicSe;
  const double x_lo = periodic ? 0.0 : basis.x_domain.center - basis.x_domain.half_width;
  const double x_hi = periodic ? basis.period : basis.x_domain.center + basis.x_domain.half_width;
  const double v_lo = data_.xdot_range.min;
  const double v_hi = data_.xdot_range.max;
  const int coarse = std::max(2, grid_points / 8);
  // Largest |f(a_{i+1}) − f(a_i)| / Δa along the fine axis, over `coarse` lines of the other axis.
  const auto largest_quotient = [&](double lo, double hi, double other_lo, double other_hi, bool along_x) {
    const double h = (hi - lo) / (grid_points - 1);
    double largest = 0.0;
    for (int j = 0; j < coarse; ++j) {
      const double other = other_lo + (other_hi - other_lo) * j / (coarse - 1);
      const auto f = [&](double a) {
        return along_x ? PredictConfidenceWeightedMean(a, other) : PredictConfidenceWeightedMean(other, a);
      };
      double previous = f(lo);
      for (int i = 1; i < grid_points; ++i) {
        const double current = f(lo + i * h);
        largest = std::max(largest, std::abs(current - previous) / h);
        previous = current;
      }
    }
    return largest;
  };
  GprLipschitzConstants out;
  out.position = out.position_sampled = largest_quotient(x_lo, x_hi, v_lo, v_hi, true);
  out.velocity = out.velocity_sampled = v_hi > v_lo ? largest_quotient(v_lo, v_hi, x_lo, x_hi, false) : 0.0;
  return out;
}

double GprModel::MaxPosteriorStd(int grid_points) const {
  if (grid_points < 2) {
    throw std::invalid_argument("GprModel::MaxPosteriorStd: grid_points must be >= 2, got " +
                                std::to_string(grid_points));
  }
  const bool periodic = data_.kernel == GprKernel::kPeriodicSe;
  const double x_lo = periodic ? 0.0 : data_.x_range.min;
  const double x_hi = periodic ? data_.basis.period : data_.x_range.max;
  const double hx = (x_hi - x_lo) / (grid_points - 1);
  const double hv = (data_.xdot_range.max - data_.xdot_range.min) / (grid_points - 1);
  double sup = 0.0;
  for (int i = 0; i < grid_points; ++i) {
    for (int j = 0; j < grid_points; ++j) {
      double s = 0.0;
      Predict(x_lo + i * hx, data_.xdot_range.min + j * hv, nullptr, &s);
      sup = std::max(sup, s);
    }
  }
  return sup;
}

double GprModel::PosteriorErrorBound(double beta_delta, int grid_points) const {
  if (!(beta_delta > 0.0) || !std::isfinite(beta_delta)) {
    throw std::invalid_argument("GprModel::PosteriorErrorBound: beta_delta must be finite and > 0, "
                                "got " + std::to_string(beta_delta));
  }
  return beta_delta * MaxPosteriorStd(grid_points);
}

}  // namespace mb
