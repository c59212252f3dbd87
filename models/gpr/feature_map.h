#pragma once
// The features ψ(x, ẋ) of a GprBasis (basis.h) compiled for the real-time queries of GprModel
// (gpr_model.h): the posterior mean ψᵀβ (eq. 22/24 in weight space) and the quadratic form ψᵀΣψ of the
// posterior variance (eq. 23).
//
// What is done once, at construction: 1/τ, the Hilbert domains' lower ends, 1/L and L^(−1/2); the feature
// function of the kernel ("PS" or "DS"), so that no query branches on the kernel type; and the instruction
// set: on x86-64 the kernels are compiled three times (baseline SSE2, AVX2 + FMA, AVX-512F) and the widest
// the CPU supports is chosen (GCC/Clang `__builtin_cpu_supports`). GprModel also packs its fitted β once
// (GprPackedWeights: zero-padded blocks of eight, no remainder per call).
//
// Per query, in eight-lane vectors and fused with the multiply-adds with β (ψ is written only if asked
// for): the first eight features of each input axis directly, as sines of quarter-turn counts (the periodic
// [cos θ, sin θ, …, cos 4θ, sin 4θ] and the Hilbert sin θ…sin 8θ, one vector polynomial each, no libm
// call); the rest by the Chebyshev recurrence f(j + L) = 2cos Lθ·f(j) − f(j − L), L = 4 harmonics (eight
// lanes of cosines and sines) or 8 (Hilbert sines), one multiply-add per eight features. No division, no
// branch on the data, no allocation.
//
// Round-off: the features equal EvaluateGprBasis's and the definitions of basis.h (one std::sin per
// feature) to about 1e-13 (the recurrences lose a few ulps per step; tests/gpr/feature_map_test.cc bounds it
// at 1e-12); fused multiply-adds where the CPU has them change results in the last bits only, so results
// may differ between CPUs at the level of round-off, never between calls on one CPU, nor between the
// packed and the unpacked β.

#include <cstddef>
#include <string_view>
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

/// A Hilbert axis of basis.h with its constants: ψ_j(u) = amplitude·sin(j·(u − lower)·quarter_turns_per_unit·π/2)
/// for |u − center| ≤ half_width, else 0; j = 1…count.
struct GprHilbertAxis {
  double center = 0.0;                  ///< c [input unit]
  double half_width = 1.0;              ///< L [input unit]
  double lower = 0.0;                   ///< c − L
  double quarter_turns_per_unit = 0.0;  ///< 1/L [quarter turns per input unit]: θ = (u − lower)/L · π/2
  double amplitude = 0.0;               ///< L^(−1/2)
  int count = 0;                        ///< m
};

/// The per-query constants of a basis (see the file comment).
struct GprFeatureConstants {
  int feature_count = 0;         ///< M
  int position_count = 0;        ///< 2J + 1 ("PS") or m_x ("DS"): the offset of the velocity features
  int constant_count = 0;        ///< 1 ("PS": ψ_0 = 1) or 0 ("DS")
  int harmonics = 0;             ///< J ("PS")
  double inverse_period = 0.0;   ///< 1/τ [1/m] ("PS")
  GprHilbertAxis x_axis;         ///< "DS"
  GprHilbertAxis xdot_axis;
};

/// Where a query reads β: the lanes of the position features after the constant one (PS: the 2J periodic
/// features, DS: the m_x Hilbert features of x), those of the velocity features, and PS's β_0 (0 for DS).
struct GprWeightBlocks {
  const double* position = nullptr;
  const double* velocity = nullptr;
  double constant = 0.0;
};

/// A weight vector β packed for GprFeatureMap::Dot, built once (GprModel packs its fitted β so): the position
/// and velocity blocks of GprWeightBlocks each zero-padded to a multiple of eight and starting on a cache line,
/// so that every query reads whole aligned blocks. The dot product has the bits of the unpacked β's.
class GprPackedWeights final {
 public:
  GprPackedWeights() = default;
  /// Packs β (length constants.feature_count). Allocates (std::bad_alloc is all it throws).
  GprPackedWeights(const GprFeatureConstants& constants, const double* beta);
  GprWeightBlocks blocks() const noexcept {
    const GprFeatureLanes* lanes = lanes_.data();
    return {lanes == nullptr ? nullptr : lanes->v,
            velocity_block_ < lanes_.size() ? lanes_[velocity_block_].v : nullptr, constant_};
  }

 private:
  std::vector<GprFeatureLanes> lanes_;
  std::size_t velocity_block_ = 0;  ///< index in lanes_ of the first velocity block
  double constant_ = 0.0;
};

/// What the "DS" quadratic form reads of a GprSeriesCovariance (zero-padded blocks of eight).
struct GprSeriesCovarianceView {
  const double* x_series = nullptr;     ///< A_d of x, d = 0…2m_x
  const double* xdot_series = nullptr;  ///< A_d of ẋ, d = 0…2m_ẋ
  const double* cross = nullptr;        ///< Σ_xẋ: m_ẋ columns of cross_blocks blocks of eight rows
  int x_series_blocks = 0;
  int xdot_series_blocks = 0;
  int cross_blocks = 0;
};

/// The covariance Σ (M×M, the fitted Cov β) of a "DS" basis in the form its quadratic form ψᵀΣψ reads least of,
/// built once (GprModel, for "DS"). With ψ_x,j = a_x sin jθ and ψ_ẋ,k = a_ẋ sin kφ (basis.h),
/// sin a·sin b = ½[cos(a − b) − cos(a + b)] turns each diagonal block into a cosine series, exactly:
///   ψ_xᵀ Σ_xx ψ_x = Σ_{d=0}^{2m_x} A_d cos dθ,  A_d = (a_x²/2)(Σ_{|j−k|=d} Σ_jk − Σ_{j+k=d} Σ_jk)
/// (and likewise for ẋ), while the cross block Σ_xẋ (m_x × m_ẋ) stays a matrix. About 2(m_x + m_ẋ) + m_x·m_ẋ
/// doubles instead of M²/2: for m_x = 135, m_ẋ = 24, 28 KB instead of 101 KB.
class GprSeriesCovariance final {
 public:
  GprSeriesCovariance() = default;
  /// Transforms `sigma` (M×M, only its lower triangle read) for a "DS" map's constants. Allocates
  /// (std::bad_alloc is all it throws).
  GprSeriesCovariance(const GprFeatureConstants& constants, const Eigen::Ref<const Eigen::MatrixXd>& sigma);
  GprSeriesCovarianceView view() const noexcept {
    return {Data(x_series_), Data(xdot_series_), Data(cross_), static_cast<int>(x_series_.size()),
            static_cast<int>(xdot_series_.size()), cross_blocks_};
  }

 private:
  static const double* Data(const std::vector<GprFeatureLanes>& v) noexcept {
    return v.empty() ? nullptr : v.front().v;
  }
  std::vector<GprFeatureLanes> x_series_;
  std::vector<GprFeatureLanes> xdot_series_;
  std::vector<GprFeatureLanes> cross_;
  int cross_blocks_ = 0;
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
  /// Switches to the kernels of `name` ("baseline", "avx2_fma" or "avx512f") if this build has them and the CPU
  /// supports them, and returns true; else returns false and changes nothing. For tests: every set gives the
  /// same results to round-off, and the constructor's choice is the widest.
  bool UseInstructionSet(std::string_view name) noexcept;

  /// ψ(x, ẋ)ᵀβ for β of length M; x [m] and ẋ [m/s] finite (ẋ clamped by the caller if wanted).
  double Dot(const double* beta, double x, double xdot) const noexcept {
    return kernels_->dot[kind_][0](constants_, BlocksOf(beta), x, xdot, nullptr);
  }
  /// ψ(x, ẋ)ᵀβ for β packed by GprPackedWeights with this map's constants(): the bits of the overload above.
  double Dot(const GprPackedWeights& beta, double x, double xdot) const noexcept {
    return kernels_->dot[kind_][1](constants_, beta.blocks(), x, xdot, nullptr);
  }
  /// Writes ψ(x, ẋ) (M values, the layout of basis.h) to `psi` and returns ψᵀβ, the same bits as Dot.
  /// A Hilbert axis outside its domain gives 0 for its features, as EvaluateGprBasis does.
  double EvaluateAndDot(const double* beta, double x, double xdot, double* psi) const noexcept {
    return kernels_->dot[kind_][0](constants_, BlocksOf(beta), x, xdot, psi);
  }
  /// EvaluateAndDot with β packed: the bits of the overload above.
  double EvaluateAndDot(const GprPackedWeights& beta, double x, double xdot, double* psi) const noexcept {
    return kernels_->dot[kind_][1](constants_, beta.blocks(), x, xdot, psi);
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
  /// ψᵀΣψ for a "DS" map's Σ transformed by GprSeriesCovariance, at the (x, ẋ) whose features `psi` holds
  /// (EvaluateAndDot's, ẋ as given there): the value of the overloads above to round-off. Writes zeros to
  /// psi.values[M, M₈).
  double QuadraticForm(const GprSeriesCovariance& sigma, double x, double xdot,
                       GprFeatureBuffer& psi) const noexcept {
    const int m = constants_.feature_count;
    for (int k = m; k < (m + 7) / 8 * 8; ++k) psi.values[k] = 0.0;
    return kernels_->series_quadratic_form(constants_, sigma.view(), x, xdot, psi.values);
  }
  /// Σ_k s_k ψ_k² for M-vectors s and ψ.
  double WeightedSquares(const double* s, const double* psi) const noexcept {
    return kernels_->weighted_squares(s, psi, constants_.feature_count);
  }

  /// One instruction set's kernels (feature_map.cc); `dot` is indexed by kernel (0 "PS", 1 "DS") and by the
  /// layout of β (0 the caller's, 1 packed). A dot kernel writes ψ when its last argument is not null.
  struct Kernels {
    const char* name;
    double (*dot[2][2])(const GprFeatureConstants&, const GprWeightBlocks&, double, double, double*) noexcept;
    double (*quadratic_form)(const double*, const double*, int) noexcept;
    double (*packed_quadratic_form)(const GprFeatureLanes*, const double*, int) noexcept;
    double (*weighted_squares)(const double*, const double*, int) noexcept;
    double (*series_quadratic_form)(const GprFeatureConstants&, const GprSeriesCovarianceView&, double, double,
                                    const double*) noexcept;
  };

 private:
  GprWeightBlocks BlocksOf(const double* beta) const noexcept {
    return {beta + constants_.constant_count, beta + constants_.position_count,
            constants_.constant_count > 0 ? beta[0] : 0.0};
  }
  GprFeatureConstants constants_;
  int kind_ = 1;
  const Kernels* kernels_;
};

}  // namespace mb
