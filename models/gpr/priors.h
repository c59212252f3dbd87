#pragma once
// Hyperparameter priors of the MAP fit: a log-normal density and hard bounds per parameter.

#include <array>
#include <limits>

#include <Eigen/Core>

#include "models/gpr/basis.h"
#include "models/gpr/kernels.h"

namespace mb {

/// log θ ~ N(log median, log_sd²), restricted to [lower, upper] (natural units of the
/// parameter). log_sd = +∞ gives a flat prior (bounds only).
struct GprParameterPrior {
  double median = 1.0;
  double log_sd = std::numeric_limits<double>::infinity();
  double lower = 0.0;
  double upper = std::numeric_limits<double>::infinity();
};

/// One prior per hyperparameter, indexed by GprParameter.
using GprPriors = std::array<GprParameterPrior, kGprParameterCount>;

/// The documented default priors (docs/gpr.md). With s² the variance of the centred targets,
/// R_x, R_ẋ the trained ranges and τ the given period:
///   σ²_{f,x}, σ²_{f,ẋ}: median s²/2, log_sd ln 10, bounds [1e-6 s², 1e2 s²]
///   σ²_n:               median s²/20, log_sd ln 10, bounds [1e-5 s², 2 s²]
///   ℓ_x "PS":           median 1, log_sd 1, bounds [0.15, 20] (dimensionless, eq. 20)
///   ℓ_x "DS":           median τ/4, log_sd 1, bounds [τ/10, max(R_x, τ)]
///   ℓ_ẋ:                median R_ẋ/3, log_sd 0.5, bounds [R_ẋ/10, 5 R_ẋ] — keeps the velocity
///                       length scale on the scale of the trained velocity range, so the fit
///                       cannot collapse it onto the few scan velocities
///   τ:                  median τ, log_sd 0.02 (2 %), bounds [0.9 τ, 1.1 τ] (used only when the
///                       period is estimated)
/// Throws std::invalid_argument if s², R_x, R_ẋ or τ is not finite and > 0.
GprPriors DefaultGprPriors(GprKernel kernel, double period, GprRange x_range, GprRange xdot_range,
                           double target_variance);

/// Σ_i log prior_i(θ_i) over the parameters with free[i] (up to a constant), and its gradient in
/// log space added to `gradient` (length kGprParameterCount) if given.
double GprLogPrior(const GprPriors& priors, const Eigen::Ref<const Eigen::VectorXd>& theta,
                   const std::array<bool, kGprParameterCount>& free, Eigen::VectorXd* gradient);

/// Checks a prior set: 0 < lower ≤ median ≤ upper, finite lower/median, log_sd > 0. Throws
/// std::invalid_argument naming the parameter ("priors.length_scale_xdot: ...").
void ValidateGprPriors(const GprPriors& priors);

}  // namespace mb
