#pragma once
// Weight-space (feature) form of the TISO-GPR kernels: k(a, b) ≈ Σ_k s_k ψ_k(a) ψ_k(b), with
// unscaled basis functions ψ_k and spectral weights s_k ≥ 0 that carry all dependence on the
// signal variances and length scales. The sum kernel of eq. 19 / 27 becomes the concatenation
// [position features | velocity features].
//
//  * Periodic kernel eq. 20, exact Fourier–Bessel expansion (Solin & Särkkä 2014, "Explicit link
//    between periodic covariance functions and state space models", eq. 13): with z = 1/ℓ²,
//    ω = 2π/τ, exp(−2 sin²(ωr/2)/ℓ²) = e^{−z} I_0(z) + Σ_{j≥1} 2 e^{−z} I_j(z) cos(jωr), so
//    ψ = [1, cos(ωx), sin(ωx), …, cos(Jωx), sin(Jωx)], s = σ²·[q_0², q_1², q_1², …, q_J², q_J²].
//    The weights q_j² = c_j e^{−z} I_j(z) sum to 1; the truncation error of the kernel is the
//    tail Σ_{j>J} q_j² (relative to σ²), and J is the smallest harmonic count with tail ≤ tol.
//  * SE kernel eq. 21, Hilbert-space expansion (Solin & Särkkä 2020, "Hilbert space methods for
//    reduced-rank Gaussian process regression", Stat. Comput. 30, eq. 20): on the domain
//    [c − L, c + L], ψ_j(u) = L^{−1/2} sin(πj(u − c + L)/(2L)), j = 1…m, and
//    s_j = S(√λ_j) with λ_j = (πj/(2L))², S(ω) = σ² √(2π) ℓ exp(−ℓ²ω²/2). Outside the domain
//    ψ_j = 0.
//
// Sizes from a tolerance `tol` (relative to σ²):
//   margin   d = ℓ·max(3, sqrt(ln(1/tol)/2)): the Dirichlet boundary adds image terms of size
//            ≤ σ² exp(−2d²/ℓ²) ≤ σ²·tol for inputs inside [lo, hi]; L = (hi − lo)/2 + d.
//   count    m = ceil(2L·sqrt(2 ln(1/tol))/(πℓ)): the spectral tail beyond ω_m = πm/(2L) is
//            σ² erfc(ℓω_m/√2) < σ²·tol.

#include <Eigen/Core>

#include "models/gpr/kernels.h"

namespace mb {

/// Largest number of features a basis may have. Prediction keeps its scratch on the stack
/// (8 KiB), so this bounds it; fits whose hyperparameters need more throw.
inline constexpr int kMaxGprFeatures = 1024;

/// Closed interval [min, max] of a trained input.
struct GprRange {
  double min = 0.0;
  double max = 0.0;
};

/// Hilbert-space domain [center − half_width, center + half_width] with `count` eigenfunctions.
struct HilbertDomain {
  double center = 0.0;
  double half_width = 1.0;  ///< L, in the input's unit
  int count = 0;            ///< m
};

/// The feature layout of one model. "PS": 2·harmonics + 1 periodic features of x, then
/// xdot_domain.count SE features of ẋ. "DS": x_domain.count SE features of x, then
/// xdot_domain.count SE features of ẋ.
struct GprBasis {
  GprKernel kernel = GprKernel::kPeriodicSe;
  double period = 0.0225;  ///< τ [m] the periodic features were built with ("PS")
  int harmonics = 0;       ///< J ("PS")
  HilbertDomain x_domain;  ///< "DS" only
  HilbertDomain xdot_domain;
};

/// Number of position features (2J + 1 for "PS", m_x for "DS").
int GprPositionFeatureCount(const GprBasis& basis) noexcept;
/// Total number of features M.
int GprFeatureCount(const GprBasis& basis) noexcept;

/// Fourier–Bessel weights q_j² = c_j e^{−z} I_j(z), j = 0…harmonics (c_0 = 1, c_j = 2), z = 1/ℓ²,
/// computed by Miller's backward recurrence of the ratios I_j/I_{j−1} normalised with
/// Σ q_j² = 1 — the exponentially scaled form, free of overflow for any ℓ. If `dlog_dlogl` is
/// given it receives ∂log q_j²/∂log ℓ (same length). Throws std::invalid_argument for ℓ ≤ 0 or
/// harmonics < 0.
Eigen::VectorXd PeriodicSpectralWeights(double length_scale, int harmonics,
                                        Eigen::VectorXd* dlog_dlogl = nullptr);

/// Smallest J with Σ_{j>J} q_j² ≤ tolerance. Throws std::invalid_argument for ℓ ≤ 0 or
/// tolerance outside (0, 1).
int PeriodicHarmonicsForTolerance(double length_scale, double tolerance);

/// Hilbert domain for an SE kernel of length scale ℓ on inputs in `range`, sized by the rules
/// in the file comment. Throws std::invalid_argument for ℓ ≤ 0, an empty or non-finite range,
/// or a tolerance outside (0, 1).
HilbertDomain HilbertDomainForTolerance(GprRange range, double length_scale, double tolerance);

/// Basis that represents the kernel at `hp` within `tolerance` for inputs in the trained ranges.
/// Throws std::invalid_argument (as above) and std::runtime_error if more than kMaxGprFeatures
/// features would be needed (the message names the length scale that causes it).
GprBasis ChooseGprBasis(GprKernel kernel, const GprHyperparameters& hp, GprRange x_range,
                        GprRange xdot_range, double tolerance);

/// True if `basis` (built for the same ranges) already meets `tolerance` at `hp`: enough
/// harmonics / eigenfunctions and a domain at least as wide as HilbertDomainForTolerance asks.
bool GprBasisSuffices(const GprBasis& basis, const GprHyperparameters& hp, GprRange x_range,
                      GprRange xdot_range, double tolerance);

/// Spectral weights s (length M) of `basis` at `hp`, and optionally ∂log s_k/∂θ_i
/// (M × kGprParameterCount; the period and noise columns are 0 — the period moves the basis,
/// not the weights). Throws std::invalid_argument if hp.period differs from basis.period for "PS".
void GprSpectralWeights(const GprBasis& basis, const GprHyperparameters& hp, Eigen::VectorXd* s,
                        Eigen::MatrixXd* dlog_s = nullptr);

/// Writes ψ(x, ẋ) (length M) to `psi`. No allocation. Inputs outside a Hilbert domain give 0
/// for that domain's features (no clamping here; GprModel clamps ẋ).
void EvaluateGprBasis(const GprBasis& basis, double x, double xdot, double* psi) noexcept;

/// Writes ∂ψ/∂x and ∂ψ/∂ẋ (each length M; position features depend on x only, velocity
/// features on ẋ only, so the other entries are 0).
void EvaluateGprBasisDerivatives(const GprBasis& basis, double x, double xdot, double* dpsi_dx,
                                 double* dpsi_dxdot) noexcept;

/// Writes ∂ψ_k/∂τ at x (length M; nonzero only for "PS" periodic features): used when the
/// period is estimated.
void EvaluateGprBasisPeriodDerivative(const GprBasis& basis, double x, double* dpsi_dtau) noexcept;

/// Angular frequency of each feature in its own input (jω for harmonic j, √λ_j for an
/// eigenfunction); |ψ_k^{(n)}| ≤ sup|ψ_k|·freq_k^n. Writes M values.
void GprBasisFrequencies(const GprBasis& basis, double* frequency) noexcept;

/// Σ_k β_k ψ_k(x, ẋ) without storing ψ: O(M), no allocation. `beta` has length M.
double DotGprBasis(const GprBasis& basis, const double* beta, double x, double xdot) noexcept;

}  // namespace mb
