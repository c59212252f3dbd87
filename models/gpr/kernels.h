#pragma once
// Covariance functions of the two-input single-output GP (TISO-GPR) of the seed paper
// (reference/paper-tisogpr-dob.txt), their derivatives, and the kernel matrix.
//
// Inputs are position x [m] and velocity ẋ [m/s]; outputs are in the units of the regressed
// disturbance squared (N² for a force). Every kernel acts on one input only (GPyTorch's
// `active_dims`), and the two-input kernels are sums (eq. 19, eq. 27).

#include <array>
#include <string_view>

#include <Eigen/Core>

namespace mb {

/// Which two-input kernel: "PS" = periodic(x) + SE(ẋ), eq. 19 (the paper's proposal);
/// "DS" = SE(x) + SE(ẋ), eq. 27 (the paper's baseline).
enum class GprKernel { kPeriodicSe, kSeSe };

/// "PS" or "DS".
std::string_view GprKernelName(GprKernel kernel) noexcept;
/// Parses "PS" or "DS" (exact spelling). Throws std::invalid_argument naming the accepted values.
GprKernel ParseGprKernel(std::string_view name);

/// Hyperparameters of eq. 19–21 / 27 plus the noise of eq. 16. All strictly positive.
/// For "PS", length_scale_x is the dimensionless ℓ_x of eq. 20; for "DS" it is a length [m].
/// `period` is τ [m] of eq. 20 (the magnet pole pitch); "DS" ignores it.
struct GprHyperparameters {
  double signal_variance_x = 1.0;     ///< σ²_{f,x}
  double length_scale_x = 1.0;        ///< ℓ_x
  double signal_variance_xdot = 1.0;  ///< σ²_{f,ẋ}
  double length_scale_xdot = 1.0;     ///< ℓ_ẋ [m/s]
  double noise_variance = 1e-2;       ///< σ²_n
  double period = 0.0225;             ///< τ [m]
};

/// Index of each hyperparameter in the log-space vector θ used by gradients, priors and the
/// optimiser: θ = log(σ²_{f,x}, ℓ_x, σ²_{f,ẋ}, ℓ_ẋ, σ²_n, τ).
enum GprParameter : int {
  kLogSignalVarianceX = 0,
  kLogLengthScaleX = 1,
  kLogSignalVarianceXdot = 2,
  kLogLengthScaleXdot = 3,
  kLogNoiseVariance = 4,
  kLogPeriod = 5,
  kGprParameterCount = 6,
};

/// Name of a log-space hyperparameter, e.g. "length_scale_xdot" (the JSON key of the model file).
std::string_view GprParameterName(int parameter) noexcept;

/// Periodic kernel eq. 20: σ² exp(−2 sin²(π|a−b|/τ)/ℓ²). ℓ dimensionless, τ [m].
double PeriodicKernel(double a, double b, double signal_variance, double length_scale,
                      double period) noexcept;

/// Squared-exponential kernel eq. 21: σ² exp(−(a−b)²/(2ℓ²)).
double SquaredExponentialKernel(double a, double b, double signal_variance,
                                double length_scale) noexcept;

/// Two-input kernel k((x1, ẋ1), (x2, ẋ2)) without noise: eq. 19 for "PS", eq. 27 for "DS".
double TisoKernel(GprKernel kernel, const GprHyperparameters& hp, double x1, double xdot1,
                  double x2, double xdot2) noexcept;

/// Derivatives of TisoKernel with respect to the log-space parameters θ (indices GprParameter);
/// the noise entry is 0 (noise is not part of k) and the period entry is 0 for "DS".
std::array<double, kGprParameterCount> TisoKernelGradient(GprKernel kernel,
                                                          const GprHyperparameters& hp,
                                                          double x1, double xdot1, double x2,
                                                          double xdot2) noexcept;

/// Kernel matrix K_ij = k(x_i, x_j) (N×N, no noise) for inputs x, ẋ of equal length N.
/// Throws std::invalid_argument if the lengths differ.
Eigen::MatrixXd TisoKernelMatrix(GprKernel kernel, const GprHyperparameters& hp,
                                 const Eigen::Ref<const Eigen::VectorXd>& x,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot);

/// Cross-kernel matrix K_ij = k(a_i, b_j) (Na×Nb). Throws std::invalid_argument on length mismatch.
Eigen::MatrixXd TisoKernelMatrix(GprKernel kernel, const GprHyperparameters& hp,
                                 const Eigen::Ref<const Eigen::VectorXd>& x_a,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot_a,
                                 const Eigen::Ref<const Eigen::VectorXd>& x_b,
                                 const Eigen::Ref<const Eigen::VectorXd>& xdot_b);

/// Converts between GprHyperparameters and the log-space vector θ (length kGprParameterCount).
Eigen::VectorXd ToLogParameters(const GprHyperparameters& hp);
/// Inverse of ToLogParameters. Throws std::invalid_argument if θ has the wrong length.
GprHyperparameters FromLogParameters(const Eigen::Ref<const Eigen::VectorXd>& theta);

}  // namespace mb
