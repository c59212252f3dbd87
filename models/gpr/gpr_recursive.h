#pragma once
// Learning online in weight space (issue 14, beyond the paper): the posterior over the coefficients β of the model's
// basis, updated one observation at a time. With f(x, ẋ) = ψ(x, ẋ)ᵀβ, prior β ~ N(0, S), S = diag(s) (the spectral
// weights, models/gpr/basis.h) and an observation d = mean + ψᵀβ + ε, ε ~ N(0, σ²_n), the exact Bayesian update is
// the Kalman / recursive-least-squares step (Särkkä 2013, "Bayesian Filtering and Smoothing", §3.4; Rasmussen &
// Williams 2006, §2.1.1):
//   k = Pψ / (σ²_n + ψᵀPψ),   m ← m + k (d − mean − ψᵀm),   P ← P − k (Pψ)ᵀ
// O(M²) per observation, no allocation. After N observations from the prior with no forgetting, (m, P) equal the
// batch posterior of models/gpr/weight_space.h on the same N samples (test GprRecursive.MatchesTheBatchPosterior).
//
// Drift (a motor warming up, wear): exponential forgetting of the information, P ← P/λ before each update,
// 0 < λ ≤ 1 (Ljung & Söderström 1983, "Theory and Practice of Recursive Identification", §2.6): old observations
// weigh λ^k, the memory is about 1/(1 − λ) observations. Directions the data no longer excite would wind P up
// without bound; here each weight's variance is bounded by its prior variance s_j (row and column j scaled by
// √(s_j/P_jj) when P_jj exceeds it), so an unexcited weight returns to its prior uncertainty and no further — the
// bounded covariance of the EFRA algorithm (Salgado, Goodwin & Middleton 1988, Int. J. Control 47) in its
// simplest form. (Adding (1 − λ)·diag(s) to P instead, as process noise, forgets far faster than 1/(1 − λ) in the
// directions the data excite: at 1 kHz and λ = 0.9995 a memory of tens of samples.) λ = 1: no forgetting.

// Hyperparameters, basis and the training mean stay those of the model the learner starts from.

#include <Eigen/Core>

#include "models/gpr/gpr_model.h"

namespace mb {

/// One observation's update of a weight posterior (m, P) held by the caller — the gpr block keeps it in its
/// discrete state. The observation: d (the model's disturbance unit, e.g. N) at position x [m] and velocity ẋ [m/s].
/// With forgetting λ < 1, first P ← P/λ with each P_jj bounded by s_j (s = model.spectral_weights()); then the
/// Kalman step above with ψ = ψ(x, clamp(ẋ)) and d − mean. `weights` m: M doubles; `covariance` P: M×M doubles,
/// column-major, both triangles kept symmetric (M = model.feature_count()). O(M²), noexcept, no allocation (scratch
/// on the stack, M ≤ kMaxGprFeatures). A non-finite input is ignored and returns false; so is λ outside (0, 1].
bool UpdateGprWeightPosterior(const GprModel& model, double forgetting, double x, double xdot, double d,
                              double* weights, double* covariance) noexcept;

/// The prior over the weights as a posterior to start learning from: m = 0, P = diag(s) (M and M×M,
/// column-major, written into the caller's storage).
void WriteGprPriorPosterior(const GprModel& model, double* weights, double* covariance) noexcept;

class GprRecursivePosterior final {
 public:
  /// Starts from `model`'s posterior (weights, covariance), or, with `from_prior`, from the prior (β = 0, P = S:
  /// a model that knows its basis, hyperparameters and mean but no data). Allocates its M-sized state here.
  /// @throws std::invalid_argument if forgetting is not in (0, 1].
  explicit GprRecursivePosterior(const GprModel& model, double forgetting = 1.0, bool from_prior = false);

  /// Absorbs one observation d (the disturbance, same unit as the model's) at position x [m] and velocity ẋ [m/s]
  /// (ẋ clamped to the trained range, as the model predicts). O(M²), noexcept, no allocation. A non-finite input is
  /// ignored and returns false.
  bool Update(double x, double xdot, double d) noexcept;

  /// Posterior mean mean + ψ(x, clamp(ẋ))ᵀm at the current state. O(M), no allocation; non-finite → the mean.
  double PredictPosteriorMean(double x, double xdot) const noexcept;

  /// The current (m, P) as a view for GprModel's predictions (std, confidence weight).
  GprPosteriorView posterior() const noexcept { return {weights_.data(), covariance_.data()}; }

  const Eigen::VectorXd& weights() const noexcept { return weights_; }       ///< m (M)
  const Eigen::MatrixXd& covariance() const noexcept { return covariance_; }  ///< P (M × M)
  long long updates() const noexcept { return updates_; }
  const GprModel& model() const noexcept { return model_; }

 private:
  GprModel model_;
  double forgetting_;
  Eigen::VectorXd weights_;
  Eigen::MatrixXd covariance_;
  long long updates_ = 0;
};

}  // namespace mb
