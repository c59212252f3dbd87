#include "models/gpr/gpr_recursive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "models/gpr/basis.h"

namespace mb {

bool UpdateGprWeightPosterior(const GprModel& model, double forgetting, double x, double xdot, double d,
                              double* weights, double* covariance) noexcept {
  if (!std::isfinite(x) || !std::isfinite(xdot) || !std::isfinite(d)) return false;
  if (!(forgetting > 0.0 && forgetting <= 1.0)) return false;
  using Scratch = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxGprFeatures, 1>;  // on the stack
  const GprModelData& data = model.data();
  const Eigen::Index m = model.feature_count();
  Eigen::Map<Eigen::VectorXd> mean(weights, m);
  Eigen::Map<Eigen::MatrixXd> p(covariance, m, m);
  Scratch psi(m);
  Scratch p_psi(m);
  EvaluateGprBasis(data.basis, x, std::clamp(xdot, data.xdot_range.min, data.xdot_range.max), psi.data());
  if (forgetting < 1.0) {
    // Exponential forgetting of the information, P ← P/λ, with each weight's variance bounded by its prior
    // variance s_j: row and column j scaled by √(s_j/P_jj) where P_jj > s_j (a diagonal congruence: P stays
    // positive semidefinite).
    const Eigen::VectorXd& s = model.spectral_weights();
    // P ← D·P·D in one pass, column by column: D_j = 1/√λ, or √(s_j/P_jj) where P_jj/λ would exceed s_j.
    Scratch scale(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      scale(j) = p(j, j) > forgetting * s(j) ? std::sqrt(s(j) / p(j, j)) : 1.0 / std::sqrt(forgetting);
    }
    for (Eigen::Index j = 0; j < m; ++j) p.col(j).array() *= scale(j) * scale.array();
  }
  p_psi.noalias() = p.selfadjointView<Eigen::Lower>() * psi;
  const double innovation_variance = data.hyperparameters.noise_variance + psi.dot(p_psi);
  const double innovation = d - data.mean - psi.dot(mean);
  mean.noalias() += (innovation / innovation_variance) * p_psi;
  // P ← P − (Pψ)(Pψ)ᵀ / (σ²_n + ψᵀPψ), both triangles (the product above reads the lower one).
  p.noalias() -= (1.0 / innovation_variance) * p_psi * p_psi.transpose();
  return true;
}

void WriteGprPriorPosterior(const GprModel& model, double* weights, double* covariance) noexcept {
  const Eigen::Index m = model.feature_count();
  Eigen::Map<Eigen::VectorXd>(weights, m).setZero();
  Eigen::Map<Eigen::MatrixXd> p(covariance, m, m);
  p.setZero();
  p.diagonal() = model.spectral_weights();
}

GprRecursivePosterior::GprRecursivePosterior(const GprModel& model, double forgetting, bool from_prior)
    : model_(model), forgetting_(forgetting) {
  if (!(forgetting > 0.0 && forgetting <= 1.0)) {
    throw std::invalid_argument("GprRecursivePosterior: the forgetting factor must be in (0, 1], got " +
                                std::to_string(forgetting));
  }
  const GprModelData& d = model_.data();
  if (from_prior) {
    weights_.resize(model_.feature_count());
    covariance_.resize(model_.feature_count(), model_.feature_count());
    WriteGprPriorPosterior(model_, weights_.data(), covariance_.data());
  } else {
    weights_ = d.weights;
    covariance_ = d.weight_covariance;
  }
}

bool GprRecursivePosterior::Update(double x, double xdot, double d) noexcept {
  if (!UpdateGprWeightPosterior(model_, forgetting_, x, xdot, d, weights_.data(), covariance_.data())) return false;
  ++updates_;
  return true;
}

double GprRecursivePosterior::PredictPosteriorMean(double x, double xdot) const noexcept {
  return model_.PredictPosteriorMean(posterior(), x, xdot);
}

}  // namespace mb
