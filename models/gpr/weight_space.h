#pragma once
// The GP in weight space (Bayesian linear regression on the features of models/gpr/basis.h):
// y = Φw + ε, Φ = ΨD, D = diag(√s), w ~ N(0, I), ε ~ N(0, σ²_n I). Then ΦΦᵀ is the truncated
// kernel and, with A = ΦᵀΦ + σ²_n I (M×M), b = Φᵀy (Rasmussen & Williams 2006, §2.1.1–2.1.2):
//   posterior weights   w̄ = A⁻¹b,  Cov w = σ²_n A⁻¹
//   log p(y) = −(yᵀy − bᵀA⁻¹b)/(2σ²_n) − ½(N − M) log σ²_n − ½ log|A| − ½ N log 2π
// (matrix inversion and determinant lemmas). Everything depends on the data only through
// ΨᵀΨ, Ψᵀy, yᵀy and N, accumulated in one pass with memory independent of N; each evaluation
// then costs O(M³).

#include <Eigen/Core>

#include "models/gpr/basis.h"
#include "models/gpr/kernels.h"

namespace mb {

/// Sufficient statistics of a data set for one basis. y is the centred target of eq. 14.
struct GprFeatureStatistics {
  GprBasis basis;
  Eigen::MatrixXd gram;        ///< ΨᵀΨ (M×M, symmetric)
  Eigen::VectorXd projection;  ///< Ψᵀy (M)
  double sum_squares = 0.0;    ///< yᵀy
  Eigen::Index count = 0;      ///< N
  bool has_period_derivative = false;
  Eigen::MatrixXd gram_dperiod;        ///< ∂(ΨᵀΨ)/∂τ ("PS" only, when requested)
  Eigen::VectorXd projection_dperiod;  ///< ∂(Ψᵀy)/∂τ
};

/// One pass over the data, in blocks of 256 rows (rank-k updates), O(N·M²) time and O(M²)
/// memory. With `period_derivative` ("PS" only) also accumulates the τ-derivatives, needed for
/// the period gradient. x, ẋ, y: length N ≥ 1. Throws std::invalid_argument on length mismatch
/// or a non-finite sample (the message gives the row).
GprFeatureStatistics AccumulateGprFeatureStatistics(const GprBasis& basis,
                                                    const Eigen::Ref<const Eigen::VectorXd>& x,
                                                    const Eigen::Ref<const Eigen::VectorXd>& xdot,
                                                    const Eigen::Ref<const Eigen::VectorXd>& y,
                                                    bool period_derivative = false);

/// Log marginal likelihood (file comment) at `hp`, and optionally its gradient in log space
/// (length kGprParameterCount, order GprParameter). The period entry is filled only when the
/// statistics carry the τ-derivatives (else 0). Throws std::invalid_argument if hp.period
/// differs from the basis' period ("PS"), std::runtime_error if A is not positive definite.
double WeightSpaceLogMarginalLikelihood(const GprFeatureStatistics& stats,
                                        const GprHyperparameters& hp,
                                        Eigen::VectorXd* gradient = nullptr);

/// Posterior over the coefficients β = D w̄ of the unscaled basis: f(x, ẋ) = ψ(x, ẋ)ᵀβ.
struct GprWeightPosterior {
  Eigen::VectorXd weights;     ///< E[β] (M)
  Eigen::MatrixXd covariance;  ///< Cov β = σ²_n D A⁻¹ D (M×M)
  double log_marginal_likelihood = 0.0;
};

/// Solves for the posterior at `hp`. Throws as WeightSpaceLogMarginalLikelihood.
GprWeightPosterior SolveGprWeightPosterior(const GprFeatureStatistics& stats,
                                           const GprHyperparameters& hp);

}  // namespace mb
