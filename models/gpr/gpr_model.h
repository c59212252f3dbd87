#pragma once
// A fitted TISO-GPR disturbance model d̂(x, ẋ) = mean(d) + ψ(x, ẋ)ᵀβ (eq. 22 + eq. 24 in weight
// space), its posterior standard deviation (eq. 23), and the constants of the paper's stability
// analysis: Lipschitz constants of the posterior mean (eq. 47) and the error bound b_μ
// (Remark 1, eq. 50).

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "models/gpr/basis.h"
#include "models/gpr/feature_map.h"
#include "models/gpr/kernels.h"
#include "models/gpr/priors.h"

namespace mb {

/// Where a model came from (written to and read from the model file; informative only).
struct GprProvenance {
  std::string created_utc;      ///< ISO 8601, e.g. "2026-11-21T15:04:05Z"
  std::string library_version;  ///< motionblocks version that fitted it
  std::string solver;           ///< "exact" or "weight_space": which likelihood the MAP used
  std::string source;           ///< free text given by the caller (e.g. the log's file name)
  /// The training table's columns of x and ẋ (FitGprToLog); "" when fitted from arrays. `predict-gpr` reads
  /// these columns by default. Written to the model file only when set.
  std::string position_column, velocity_column;
  std::int64_t sample_count = 0;
  double log_marginal_likelihood = 0.0;  ///< at the MAP, of the weight-space model
  double log_posterior = 0.0;            ///< MAP objective (up to a constant)
  double fit_seconds = 0.0;
  double tolerance = 0.0;  ///< kernel truncation tolerance of the basis (relative to σ²)
  bool period_estimated = false;
  GprPriors priors{};
};

/// Everything a model file holds. Plain data; GprModel validates it.
struct GprModelData {
  GprKernel kernel = GprKernel::kPeriodicSe;
  GprHyperparameters hyperparameters;
  GprBasis basis;
  double mean = 0.0;       ///< mean(d_g) of eq. 14, added back by eq. 24
  GprRange x_range;        ///< trained position range [m]
  GprRange xdot_range;     ///< trained velocity range [m/s]
  Eigen::VectorXd weights;            ///< E[β] (M)
  Eigen::MatrixXd weight_covariance;  ///< Cov β (M×M, symmetric positive semidefinite)
  GprProvenance provenance;
};

/// Lipschitz constants of the posterior mean over all inputs (eq. 47):
/// |μ(x1, ẋ1) − μ(x2, ẋ2)| ≤ position·|x1 − x2| + velocity·|ẋ1 − ẋ2|.
/// Because μ = mean + μ_x(x) + μ_ẋ(ẋ) (the kernel is a sum) they are sup|μ_x'| and sup|μ_ẋ'|.
struct GprLipschitzConstants {
  double position = 0.0;  ///< L_x, rigorous upper bound [disturbance unit / m]
  double velocity = 0.0;  ///< L_ẋ, rigorous upper bound [disturbance unit / (m/s)]
  double position_sampled = 0.0;  ///< max |μ_x'| on the grid (a lower bound of the supremum)
  double velocity_sampled = 0.0;  ///< max |μ_ẋ'| on the grid
};

/// A posterior over a model's basis weights β other than the fitted one — an online learner's state
/// (gpr_recursive.h, the gpr block's discrete state): views, not owned. weights: E[β] (M doubles);
/// covariance: Cov β (M×M doubles, column-major, symmetric; the lower triangle is read).
struct GprPosteriorView {
  const double* weights = nullptr;
  const double* covariance = nullptr;
};

/// The fitted model. Immutable; prediction is noexcept, allocation-free and O(M) for the mean.
///
/// Inputs outside the trained ranges:
///  * ẋ is clamped to the trained velocity range [min ẋ, max ẋ] for the velocity (SE) part: the
///    SE kernel carries no information beyond the data, and the paper requires the trained
///    velocity range for reliable inference (§3.2); clamping keeps the output bounded and equal
///    to the boundary value instead of decaying to the mean.
///  * x is not clamped. "PS": the periodic part repeats with the period τ (the point of eq. 19,
///    Fig. 6 d–f). "DS": the SE position part decays to 0 as in the exact GP (Fig. 6 a–c); it is
///    exactly 0 beyond the Hilbert domain (the trained range plus a margin of ≥ 3 ℓ_x).
///  * Non-finite x or ẋ: the mean returns `mean()` (the prior mean), the std the prior std.
class GprModel final {
 public:
  /// Validates and takes `data`. Throws std::invalid_argument listing every problem found:
  /// non-finite or non-positive hyperparameters, weights or covariance of the wrong size or
  /// non-finite, an empty trained range, a basis with no or too many (> kMaxGprFeatures)
  /// features, or a "PS" basis period that differs from the hyperparameter period.
  explicit GprModel(GprModelData data);

  /// Posterior mean d̂ = mean + ψ(x, clamp(ẋ))ᵀβ (eq. 22, 24) at position x [m], velocity ẋ [m/s].
  double PredictPosteriorMean(double x, double xdot) const noexcept;

  /// Posterior mean and the posterior standard deviation of the latent f (√ of eq. 23; add
  /// noise_variance for a new observation). O(M²), no allocation. Either pointer may be null.
  ///
  /// The variance is ψᵀ Cov(β) ψ plus the prior variance the truncated basis does not carry,
  /// k(a, a) − Σ_k s_k ψ_k(a)² = σ²_x + σ²_ẋ − Σ_k s_k ψ_k(a)² (clipped at 0): the diagonal
  /// correction of the sparse-GP literature (Quiñonero-Candela & Rasmussen 2005, JMLR 6, §6,
  /// "FITC" predictive variance). It is ≤ tol·σ² where the basis represents the kernel (inside
  /// the trained ranges) and restores the prior variance where it does not: "DS" beyond its
  /// Hilbert domain, where every position feature is 0, and near the domain's Dirichlet
  /// boundary.
  void Predict(double x, double xdot, double* mean, double* std) const noexcept;

  /// Confidence weight g(x, ẋ) = clip(1 − σ²(x, ẋ)/σ_f², 0, 1) ∈ [0, 1], with σ² the posterior
  /// variance of Predict and σ_f² = σ²_x + σ²_ẋ the prior variance: 1 where the data pin the
  /// posterior down, 0 where nothing is known (σ² back at the prior). It scales the compensation
  /// where the paper uses a fixed α (eq. 53): α(x, ẋ) = α_max·g(x, ẋ), trusting the GP where it has
  /// data (the posterior variance is left to the analysis in the paper, Remark 1). O(M²), no
  /// allocation. Non-finite inputs give 0.
  double ConfidenceWeight(double x, double xdot) const noexcept;

  /// g(x, ẋ)·d̂(x, ẋ): the posterior mean scaled by the confidence weight. O(M²), no allocation.
  /// If `weight` is not null it receives g.
  double PredictConfidenceWeightedMean(double x, double xdot, double* weight = nullptr) const noexcept;

  /// Lipschitz constants of g·d̂ for the small-gain analysis with the confidence weight (eq. 47 with
  /// μ replaced by g·d̂; the weighted mean is not a sum of a position and a velocity part, so each
  /// constant is the largest difference quotient over a 2-D grid): position over one period ("PS") or
  /// the Hilbert domain ("DS"; constant beyond it) × the trained velocity range, `grid_points`
  /// along the differenced axis and grid_points/8 (≥ 2) along the other. A sampled estimate (a
  /// lower bound of the supremum that converges as the grid is refined), reported in both the
  /// bound and the sampled fields. @throws std::invalid_argument for grid_points < 16.
  GprLipschitzConstants ConfidenceWeightedLipschitzConstants(int grid_points = 256) const;

  /// The fitted posterior (weights and covariance of the model file) as a view.
  GprPosteriorView fitted_posterior() const noexcept {
    return {data_.weights.data(), data_.weight_covariance.data()};
  }
  /// PredictPosteriorMean, Predict and PredictConfidenceWeightedMean with `posterior` over this
  /// model's basis (same M) in place of the fitted one: same formulas, same cost, no allocation.
  double PredictPosteriorMean(const GprPosteriorView& posterior, double x, double xdot) const noexcept;
  void Predict(const GprPosteriorView& posterior, double x, double xdot, double* mean,
               double* std) const noexcept;
  double PredictConfidenceWeightedMean(const GprPosteriorView& posterior, double x, double xdot,
                                       double* weight = nullptr) const noexcept;
  /// s (M): the prior variances of the basis weights at the model's hyperparameters (basis.h), the
  /// prior β ~ N(0, diag s) an online learner starts from or relaxes to.
  const Eigen::VectorXd& spectral_weights() const noexcept { return spectral_weights_; }

  /// Batch forms; all vectors of one length. Throw std::invalid_argument on a length mismatch.
  void PredictPosteriorMean(const Eigen::Ref<const Eigen::VectorXd>& x,
                            const Eigen::Ref<const Eigen::VectorXd>& xdot,
                            Eigen::Ref<Eigen::VectorXd> mean) const;
  void Predict(const Eigen::Ref<const Eigen::VectorXd>& x,
               const Eigen::Ref<const Eigen::VectorXd>& xdot, Eigen::Ref<Eigen::VectorXd> mean,
               Eigen::Ref<Eigen::VectorXd> std) const;

  /// ∂μ/∂x and ∂μ/∂ẋ at (x, ẋ) (∂μ/∂ẋ = 0 outside the trained velocity range, where ẋ is clamped).
  void PosteriorMeanGradient(double x, double xdot, double* dmu_dx,
                             double* dmu_dxdot) const noexcept;

  /// Lipschitz constants of eq. 47, global (all x, all ẋ). Each is the maximum of |μ'| on a grid
  /// plus (h/2)·Σ_k |β_k| sup|ψ_k| ω_k² (a bound on |μ''| times half the spacing), hence a
  /// rigorous upper bound. Position grid: one period ("PS", μ_x is τ-periodic) or the Hilbert
  /// domain ("DS", μ_x is constant outside). Velocity grid: the trained velocity range.
  /// `grid_points` ≥ 2 per axis (default keeps the correction below ~1 % for typical models).
  GprLipschitzConstants LipschitzConstants(int grid_points = 8192) const;

  /// sup σ(x, ẋ) over the compact domain X on a grid of grid_points² points: X = one period ×
  /// trained ẋ range ("PS", σ is τ-periodic in x) or trained x range × trained ẋ range ("DS").
  /// A sampled supremum (the posterior std is smooth; refine the grid to tighten).
  double MaxPosteriorStd(int grid_points = 128) const;

  /// b_μ of Remark 1, eq. 50: β_δ · sup_X σ(x, ẋ). β_δ > 0 is the caller's confidence scaling
  /// (eq. 49; e.g. 2 or 3 for a pointwise 95 % / 99.7 % band, larger for a uniform bound, see
  /// Lederer et al. 2019). Throws std::invalid_argument for β_δ ≤ 0 or grid_points < 2.
  double PosteriorErrorBound(double beta_delta, int grid_points = 128) const;

  const GprModelData& data() const noexcept { return data_; }
  GprKernel kernel() const noexcept { return data_.kernel; }
  const GprHyperparameters& hyperparameters() const noexcept { return data_.hyperparameters; }
  double mean() const noexcept { return data_.mean; }
  GprRange x_range() const noexcept { return data_.x_range; }
  GprRange xdot_range() const noexcept { return data_.xdot_range; }
  int feature_count() const noexcept { return GprFeatureCount(data_.basis); }
  /// The basis compiled for the queries (feature_map.h): what PredictPosteriorMean and Predict evaluate.
  const GprFeatureMap& feature_map() const noexcept { return feature_map_; }

 private:
  double ClampXdot(double xdot) const noexcept;
  GprModelData data_;
  Eigen::VectorXd spectral_weights_;  ///< s (M) at the model's hyperparameters, for the variance
  double prior_variance_ = 0.0;       ///< k(a, a) = σ²_x + σ²_ẋ
  GprFeatureMap feature_map_;         ///< data_.basis with its constants precomputed
  GprPackedLowerTriangle packed_covariance_;  ///< data_.weight_covariance for the quadratic form ("PS")
  GprSeriesCovariance series_covariance_;     ///< the same for "DS"
  GprPackedWeights packed_weights_;           ///< data_.weights for the dot product
};

}  // namespace mb
