#include "models/gpr/gpr_recursive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "models/gpr/basis.h"

namespace mb {

GprRecursivePosterior::GprRecursivePosterior(const GprModel& model, double forgetting, bool from_prior)
    : model_(model), forgetting_(forgetting) {
  if (!(forgetting > 0.0 && forgetting <= 1.0)) {
    throw std::invalid_argument("GprRecursivePosterior: the forgetting factor must be in (0, 1], got " +
                                std::to_string(forgetting));
  }
  const GprModelData& d = model_.data();
  GprSpectralWeights(d.basis, d.hyperparameters, &prior_variance_);
  const Eigen::Index m = prior_variance_.size();
  if (from_prior) {
    weights_ = Eigen::VectorXd::Zero(m);
    covariance_ = prior_variance_.asDiagonal();
  } else {
    weights_ = d.weights;
    covariance_ = d.weight_covariance;
  }
  psi_ = Eigen::VectorXd::Zero(m);
  p_psi_ = Eigen::VectorXd::Zero(m);
}

bool GprRecursivePosterior::Update(double x, double xdot, double d) noexcept {
  if (!std::isfinite(x) || !std::isfinite(xdot) || !std::isfinite(d)) return false;
  const GprModelData& data = model_.data();
  const double v = std::clamp(xdot, data.xdot_range.min, data.xdot_range.max);
  EvaluateGprBasis(data.basis, x, v, psi_.data());
  if (forgetting_ < 1.0) {
    covariance_ *= forgetting_;
    covariance_.diagonal().noalias() += (1.0 - forgetting_) * prior_variance_;
  }
  p_psi_.noalias() = covariance_.selfadjointView<Eigen::Lower>() * psi_;
  const double innovation_variance = data.hyperparameters.noise_variance + psi_.dot(p_psi_);
  const double innovation = d - data.mean - psi_.dot(weights_);
  weights_.noalias() += (innovation / innovation_variance) * p_psi_;
  // P ← P − (Pψ)(Pψ)ᵀ / (σ²_n + ψᵀPψ), both triangles (the product above reads the lower one).
  covariance_.noalias() -= (1.0 / innovation_variance) * p_psi_ * p_psi_.transpose();
  ++updates_;
  return true;
}

double GprRecursivePosterior::PredictPosteriorMean(double x, double xdot) const noexcept {
  const GprModelData& data = model_.data();
  if (!std::isfinite(x) || !std::isfinite(xdot)) return data.mean;
  return data.mean + DotGprBasis(data.basis, weights_.data(), x,
                                 std::clamp(xdot, data.xdot_range.min, data.xdot_range.max));
}

}  // namespace mb
