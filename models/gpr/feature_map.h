#pragma once
// The features ψ(x, ẋ) of a GprBasis (basis.h) compiled for the real-time queries of GprModel
// (gpr_model.h): the posterior mean ψᵀβ (eq. 22/24 in weight space) and the quadratic form ψᵀΣψ of the
// posterior variance (eq. 23).
//
// What is done once, at construction: 1/τ, the Hilbert domains' lower ends, π/(2L) and L^(−1/2); the
// feature function of the kernel ("PS" or "DS"), so that no query branches on the kernel type; and the
// instruction set: on x86-64 the kernels are compiled three times (baseline SSE2, AVX2 + FMA, AVX-512F)
// and the widest the CPU supports is chosen (GCC/Clang `__builtin_cpu_supports`).
//
// Per query: one bounded sine/cosine pair per input axis (sincos.h); the periodic harmonics by the
// angle-addition recurrence in four lanes (models/physics/fourier_series.h); the Hilbert sines by the
// Chebyshev recurrence sin((j+8)θ) = 2cos 8θ·sin jθ − sin((j−8)θ) in eight lanes held in one vector
// register; then the multiply-adds. No division, no libm call, no allocation.
//
// Round-off: the features equal EvaluateGprBasis's and the definitions of basis.h (one std::sin per
// feature) to about 1e-13 (the recurrences lose a few ulps per step; tests/gpr/feature_map_test.cc bounds it
// at 1e-12); fused multiply-adds where the CPU has them change results in the last bits only, so results
// may differ between CPUs at the level of round-off, never between calls on one CPU.

#include <vector>

#include <Eigen/Core>

#include "models/gpr/basis.h"

namespace mb {

/// Scratch for one feature vector ψ: on the stack, 64-byte aligned, at most kMaxGprFeatures entries.
struct alignas(64) GprFeatureBuffer {
  double values[kMaxGprFeatures];
};

/// Eight doubles on one 64-byte cache line: the unit of GprPackedLowerTriangle.
struct alignas(64) GprFeatureLanes {
  double v[8];
};

/// The lower triangle of a symmetric M×M matrix Σ in the layout the quadratic form reads fastest, built once
/// (GprModel packs its fitted Cov β so): column blocks of eight, each holding its columns' rows from the
/// block's first column down to M rounded up to a multiple of eight (M₈), column-major within the block, in
/// cache-line units. Entries above the diagonal and the padding are 0 and the diagonal is halved, so that
/// ψᵀΣψ = 2 Σ_blocks Σ_k ψ_{j0+k} Σ_r W_rk ψ_r with every load aligned and no scalar remainder. About
/// M₈²/2 doubles.
class GprPackedLowerTriangle final {
 public:
  GprPackedLowerTriangle() = default;
  /// Packs `sigma` (M×M, only its lower triangle read). Allocates (std::bad_alloc is all it throws).
  explicit GprPackedLowerTriangle(const Eigen::Ref<const Eigen::MatrixXd>& sigma);
  int size() const noexcept { return size_; }  ///< M
  const GprFeatureLanes* data() const noexcept { return values_.data(); }

 private:
  std::vector<GprFeatureLanes> values_;
  int size_ = 0;
};

/// A Hilbert axis of basis.h with its constants: ψ_j(u) = amplitude·sin(j·(u − lower)·phase_per_unit) for
/// |u − center| ≤ half_width, else 0; j = 1…count.
struct GprHilbertAxis {
  double center = 0.0;          ///< c [input unit]
  double half_width = 1.0;      ///< L [input unit]
  double lower = 0.0;           ///< c − L
  double phase_per_unit = 0.0;  ///< π/(2L) [rad per input unit]
  double amplitude = 0.0;       ///< L^(−1/2)
  int count = 0;                ///< m
};

/// The per-query constants of a basis (see the file comment).
struct GprFeatureConstants {
  int feature_count = 0;         ///< M
  int position_count = 0;        ///< 2J + 1 ("PS") or m_x ("DS"): the offset of the velocity features
  int harmonics = 0;             ///< J ("PS")
  double inverse_period = 0.0;   ///< 1/τ [1/m] ("PS")
  GprHilbertAxis x_axis;         ///< "DS"
  GprHilbertAxis xdot_axis;
};

/// A basis compiled for evaluation. Immutable and copyable; every query is noexcept, allocation-free and
/// reads only its arguments and the constants.
class GprFeatureMap final {
 public:
  /// The map of a basis with no features (M = 0): Dot gives 0, Evaluate writes nothing.
  GprFeatureMap() noexcept;
  /// Precomputes the constants of `basis`, which the caller has validated (GprModel's constructor: a
  /// positive period, Hilbert domains with half_width > 0, M ≤ kMaxGprFeatures).
  explicit GprFeatureMap(const GprBasis& basis) noexcept;

  /// M, the length of ψ.
  int feature_count() const noexcept { return constants_.feature_count; }
  const GprFeatureConstants& constants() const noexcept { return constants_; }
  /// The instruction set the kernels use: "avx512f", "avx2_fma" or "baseline".
  const char* instruction_set() const noexcept { return kernels_->name; }

  /// ψ(x, ẋ)ᵀβ for β of length M; x [m] and ẋ [m/s] finite (ẋ clamped by the caller if wanted).
  double Dot(const double* beta, double x, double xdot) const noexcept {
    return kernels_->dot[kind_](constants_, beta, x, xdot, nullptr);
  }
  /// Writes ψ(x, ẋ) (M values, the layout of basis.h) to `psi` and returns ψᵀβ, the same bits as Dot.
  /// A Hilbert axis outside its domain gives 0 for its features, as EvaluateGprBasis does.
  double EvaluateAndDot(const double* beta, double x, double xdot, double* psi) const noexcept {
    return kernels_->dot[kind_](constants_, beta, x, xdot, psi);
  }
  /// ψᵀΣψ for the symmetric M×M matrix Σ stored column-major, of which only the lower triangle is read:
  /// Σ_j Σ_jj ψ_j² + 2 Σ_{i>j} Σ_ij ψ_i ψ_j, M(M+1)/2 multiply-adds in blocks of four columns. Not
  /// clipped: a positive semidefinite Σ gives ≥ 0 up to round-off.
  double QuadraticForm(const double* covariance, const double* psi) const noexcept {
    return kernels_->quadratic_form(covariance, psi, constants_.feature_count);
  }
  /// ψᵀΣψ for Σ packed (same M; the fitted Cov β of GprModel): the value of the overload above to round-off,
  /// with aligned loads only. Writes zeros to psi.values[M, M₈) (the padding the packed rows multiply).
  double QuadraticForm(const GprPackedLowerTriangle& sigma, GprFeatureBuffer& psi) const noexcept {
    const int m = constants_.feature_count;
    for (int k = m; k < (m + 7) / 8 * 8; ++k) psi.values[k] = 0.0;
    return kernels_->packed_quadratic_form(sigma.data(), psi.values, m);
  }
  /// Σ_k s_k ψ_k² for M-vectors s and ψ.
  double WeightedSquares(const double* s, const double* psi) const noexcept {
    return kernels_->weighted_squares(s, psi, constants_.feature_count);
  }

  /// One instruction set's kernels (feature_map.cc); `dot` is indexed by kernel: 0 "PS", 1 "DS". A dot
  /// kernel writes ψ when its last argument is not null.
  struct Kernels {
    const char* name;
    double (*dot[2])(const GprFeatureConstants&, const double*, double, double, double*) noexcept;
    double (*quadratic_form)(const double*, const double*, int) noexcept;
    double (*packed_quadratic_form)(const GprFeatureLanes*, const double*, int) noexcept;
    double (*weighted_squares)(const double*, const double*, int) noexcept;
  };

 private:
  GprFeatureConstants constants_;
  int kind_ = 1;
  const Kernels* kernels_;
};

}  // namespace mb
