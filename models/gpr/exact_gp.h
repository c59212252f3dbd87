#pragma once
// The exact (Cholesky) GP of the seed paper's eq. 22–23: the reference the weight-space form is
// tested against. O(N³) time and O(N²) memory: keep N to a few thousand.

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "models/gpr/kernels.h"

namespace mb {

/// Log marginal likelihood log p(y | X, θ) of the zero-mean GP with kernel `kernel` at `hp`
/// (Rasmussen & Williams 2006, Alg. 2.1 line 8, eq. 5.8). If `gradient` is given it receives
/// ∂/∂θ in log space (length kGprParameterCount, order GprParameter; eq. 5.9:
/// ½ tr((ααᵀ − K_y⁻¹) ∂K_y/∂θ_i)). y must already be centred (eq. 14). x, ẋ, y: length N.
/// Throws std::invalid_argument on length mismatch or N = 0, std::runtime_error if
/// K + σ²_n I is not positive definite (the message gives the noise variance to raise).
double ExactLogMarginalLikelihood(GprKernel kernel, const GprHyperparameters& hp,
                                  const Eigen::Ref<const Eigen::VectorXd>& x,
                                  const Eigen::Ref<const Eigen::VectorXd>& xdot,
                                  const Eigen::Ref<const Eigen::VectorXd>& y,
                                  Eigen::VectorXd* gradient = nullptr);

/// Exact GP posterior at fixed hyperparameters (R&W Alg. 2.1): factorises K + σ²_n I once,
/// then predicts. Zero prior mean: pass the centred targets of eq. 14 and add the mean back
/// (eq. 24) yourself. Inputs are not clamped.
class ExactGp final {
 public:
  /// Copies the training inputs. Throws as ExactLogMarginalLikelihood.
  ExactGp(GprKernel kernel, const GprHyperparameters& hp,
          const Eigen::Ref<const Eigen::VectorXd>& x,
          const Eigen::Ref<const Eigen::VectorXd>& xdot,
          const Eigen::Ref<const Eigen::VectorXd>& y);

  /// Posterior mean eq. 22, k_*ᵀ (K + σ²_n I)⁻¹ y. O(N); allocates nothing.
  double PosteriorMean(double x, double xdot) const noexcept;
  /// Posterior variance of the latent f, eq. 23: k_** − k_*ᵀ (K + σ²_n I)⁻¹ k_*. O(N²); allocates.
  double PosteriorVariance(double x, double xdot) const;

  const Eigen::VectorXd& alpha() const noexcept { return alpha_; }  ///< (K + σ²_n I)⁻¹ y
  double log_marginal_likelihood() const noexcept { return log_marginal_likelihood_; }
  const GprHyperparameters& hyperparameters() const noexcept { return hp_; }

 private:
  GprKernel kernel_;
  GprHyperparameters hp_;
  Eigen::VectorXd x_;
  Eigen::VectorXd xdot_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd alpha_;
  double log_marginal_likelihood_ = 0.0;
};

}  // namespace mb
