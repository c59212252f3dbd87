#include "models/gpr/feature_map.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numbers>

#include "models/gpr/sincos.h"
#include "models/physics/fourier_series.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MB_GPR_X86_KERNELS 1
#endif

namespace mb {
namespace {

constexpr double kPi = std::numbers::pi;

// GCC/Clang vector extensions: the compiler maps them onto the registers of each function's target
// (4 SSE2 registers for V8 in the baseline kernels, 2 AVX2 registers, 1 AVX-512 register).
using V2 = double __attribute__((vector_size(16)));
using V4 = double __attribute__((vector_size(32)));
using V8 = double __attribute__((vector_size(64)));

// An unaligned vector load (by reference: a vector returned by value changes the ABI between targets).
template <typename V>
[[gnu::always_inline]] inline void LoadTo(V& v, const double* p) noexcept {
  std::memcpy(&v, p, sizeof(V));
}

// acc += c[0…lanes) ∘ p.
template <typename V>
[[gnu::always_inline]] inline void MultiplyAdd(V& acc, const double* c, const V& p) noexcept {
  V u;
  LoadTo(u, c);
  acc += u * p;
}

template <typename V>
[[gnu::always_inline]] inline void Store(double* p, const V& v) noexcept {
  std::memcpy(p, &v, sizeof(V));
}

template <typename V>
[[gnu::always_inline]] inline double Sum(const V& v) noexcept {
  constexpr std::size_t kLanes = sizeof(V) / sizeof(double);
  double pair[kLanes / 2];
  for (std::size_t k = 0; k < kLanes / 2; ++k) pair[k] = v[2 * k] + v[2 * k + 1];
  for (std::size_t width = kLanes / 2; width > 1; width /= 2) {
    for (std::size_t k = 0; k < width / 2; ++k) pair[k] = pair[2 * k] + pair[2 * k + 1];
  }
  return pair[0];
}

// floor(t) without the libm call std::floor becomes on baseline x86-64 (no SSE4.1 rounding instruction):
// truncate, step down for negative non-integers; |t| ≥ 2⁵² is already an integer.
[[gnu::always_inline]] inline double Floor(double t) noexcept {
  if (!(std::abs(t) < 0x1p52)) return t;
  const double truncated = static_cast<double>(static_cast<std::int64_t>(t));
  return truncated > t ? truncated - 1.0 : truncated;
}

// Σ_j β_j ψ_j(u) over one Hilbert axis, ψ_j = amplitude·sin(jθ), θ = (u − lower)·π/(2L); with kStore also
// writes ψ. Eight lanes of sin((j + 8n)θ) in one vector, stepped by the Chebyshev recurrence in 8θ.
template <bool kStore>
[[gnu::always_inline]] inline double HilbertDot(const GprHilbertAxis& a, double u, const double* beta,
                                                double* psi) noexcept {
  const int n = a.count;
  if (!(std::abs(u - a.center) <= a.half_width)) {
    if constexpr (kStore) {
      for (int j = 0; j < n; ++j) psi[j] = 0.0;
    }
    return 0.0;
  }
  double s1 = 0.0;
  double c1 = 0.0;
  SinCosBounded((u - a.lower) * a.phase_per_unit, &s1, &c1);
  const double s2 = 2.0 * s1 * c1;
  const double c2 = 2.0 * c1 * c1 - 1.0;
  const double s3 = s2 * c1 + c2 * s1;
  const double c3 = c2 * c1 - s2 * s1;
  const double s4 = 2.0 * s2 * c2;
  const double c4 = 2.0 * c2 * c2 - 1.0;
  const double two_c8 = 2.0 * (2.0 * c4 * c4 - 1.0);
  V8 current = {s1, s2, s3, s4, s4 * c1 + c4 * s1, s4 * c2 + c4 * s2, s4 * c3 + c4 * s3, 2.0 * s4 * c4};
  V8 previous = {-current[6], -current[5], -current[4], -s4, -s3, -s2, -s1, 0.0};  // sin((j − 8)θ)
  V8 acc = {};
  const double amplitude = a.amplitude;
  int j = 0;
  for (; j + 8 <= n; j += 8) {
    V8 b;
    LoadTo(b, beta + j);
    acc += b * current;
    if constexpr (kStore) Store(psi + j, current * amplitude);
    const V8 next = two_c8 * current - previous;
    previous = current;
    current = next;
  }
  double tail = 0.0;  // a scalar: writing single lanes of `acc` would stall on store forwarding
  for (int k = 0; j + k < n; ++k) {
    tail += beta[j + k] * current[k];
    if constexpr (kStore) psi[j + k] = amplitude * current[k];
  }
  return amplitude * (Sum(acc) + tail);
}

// "PS": ψ = [1, cos ωx, sin ωx, …, cos Jωx, sin Jωx | Hilbert features of ẋ], ωx = 2π·frac(x/τ).
template <bool kStore>
[[gnu::always_inline]] inline double PeriodicSeDot(const GprFeatureConstants& k, const double* beta, double x,
                                                   double xdot, double* psi) noexcept {
  const double t = x * k.inverse_period;
  double s1 = 0.0;
  double c1 = 0.0;
  SinCosBounded(2.0 * kPi * (t - Floor(t)), &s1, &c1);
  double acc[4] = {beta[0], 0.0, 0.0, 0.0};
  if constexpr (kStore) psi[0] = 1.0;
  ForEachHarmonic<4>(c1, s1, k.harmonics, [&](int j, double c, double s, int lane) {
    acc[lane] += beta[2 * j - 1] * c + beta[2 * j] * s;
    if constexpr (kStore) {
      psi[2 * j - 1] = c;
      psi[2 * j] = s;
    }
  });
  const double position = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  return position + HilbertDot<kStore>(k.xdot_axis, xdot, beta + k.position_count,
                                       kStore ? psi + k.position_count : nullptr);
}

// "DS": ψ = [Hilbert features of x | Hilbert features of ẋ].
template <bool kStore>
[[gnu::always_inline]] inline double SeSeDot(const GprFeatureConstants& k, const double* beta, double x,
                                             double xdot, double* psi) noexcept {
  const double position = HilbertDot<kStore>(k.x_axis, x, beta, psi);
  return position + HilbertDot<kStore>(k.xdot_axis, xdot, beta + k.position_count,
                                       kStore ? psi + k.position_count : nullptr);
}

// ψᵀCψ from the lower triangle of the column-major m×m C, four columns j…j+3 at a time: their 4×4 diagonal
// block in scalars, the rows below in vectors of V (two per step, eight accumulators), ψ loaded once per
// four columns.
template <typename V>
[[gnu::always_inline]] inline double QuadraticFormBody(const double* c, const double* psi, int m) noexcept {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
  const std::ptrdiff_t stride = m;
  double diagonal = 0.0;
  double off_diagonal = 0.0;  // Σ_{i>j} C_ij ψ_i ψ_j
  int j = 0;
  for (; j + 4 <= m; j += 4) {
    const double* c0 = c + j * stride;
    const double* c1 = c0 + stride;
    const double* c2 = c1 + stride;
    const double* c3 = c2 + stride;
    const double p0 = psi[j], p1 = psi[j + 1], p2 = psi[j + 2], p3 = psi[j + 3];
    diagonal += (c0[j] * p0 * p0 + c1[j + 1] * p1 * p1) + (c2[j + 2] * p2 * p2 + c3[j + 3] * p3 * p3);
    off_diagonal += p0 * (c0[j + 1] * p1 + c0[j + 2] * p2 + c0[j + 3] * p3) + p1 * (c1[j + 2] * p2 + c1[j + 3] * p3) +
                    p2 * c2[j + 3] * p3;
    V a0 = {}, a1 = {}, a2 = {}, a3 = {}, b0 = {}, b1 = {}, b2 = {}, b3 = {};
    int i = j + 4;
    V p, q;
    for (; i + 2 * kLanes <= m; i += 2 * kLanes) {
      LoadTo(p, psi + i);
      LoadTo(q, psi + i + kLanes);
      MultiplyAdd(a0, c0 + i, p);
      MultiplyAdd(a1, c1 + i, p);
      MultiplyAdd(a2, c2 + i, p);
      MultiplyAdd(a3, c3 + i, p);
      MultiplyAdd(b0, c0 + i + kLanes, q);
      MultiplyAdd(b1, c1 + i + kLanes, q);
      MultiplyAdd(b2, c2 + i + kLanes, q);
      MultiplyAdd(b3, c3 + i + kLanes, q);
    }
    if (i + kLanes <= m) {
      LoadTo(p, psi + i);
      MultiplyAdd(a0, c0 + i, p);
      MultiplyAdd(a1, c1 + i, p);
      MultiplyAdd(a2, c2 + i, p);
      MultiplyAdd(a3, c3 + i, p);
      i += kLanes;
    }
    const V columns = ((a0 + b0) * p0 + (a1 + b1) * p1) + ((a2 + b2) * p2 + (a3 + b3) * p3);
    double rest = 0.0;
    for (; i < m; ++i) rest += psi[i] * ((c0[i] * p0 + c1[i] * p1) + (c2[i] * p2 + c3[i] * p3));
    off_diagonal += Sum(columns) + rest;
  }
  for (; j < m; ++j) {  // the last m mod 4 columns
    const double* cj = c + j * stride;
    diagonal += cj[j] * psi[j] * psi[j];
    double column = 0.0;
    for (int i = j + 1; i < m; ++i) column += cj[i] * psi[i];
    off_diagonal += psi[j] * column;
  }
  return diagonal + 2.0 * off_diagonal;
}

// ψᵀΣψ from GprPackedLowerTriangle's layout: per block of eight columns one accumulator per column, a
// cache line of ψ and of each column per step.
template <typename V>
[[gnu::always_inline]] inline double PackedQuadraticFormBody(const GprFeatureLanes* w, const double* psi,
                                                             int m) noexcept {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
  const int padded = (m + 7) / 8 * 8;
  double total = 0.0;
  for (int j0 = 0; j0 < padded; j0 += 8) {
    const int groups = (padded - j0) / 8;
    V acc[8] = {};
    V p;
    for (int g = 0; g < groups; ++g) {
      for (int h = 0; h < 8; h += kLanes) {
        LoadTo(p, psi + j0 + 8 * g + h);
        for (int k = 0; k < 8; ++k) MultiplyAdd(acc[k], w[k * groups + g].v + h, p);
      }
    }
    V columns = {};
    for (int k = 0; k < 8; ++k) columns += acc[k] * psi[j0 + k];
    total += Sum(columns);
    w += 8 * groups;
  }
  return 2.0 * total;
}

template <typename V>
[[gnu::always_inline]] inline double WeightedSquaresBody(const double* s, const double* psi, int m) noexcept {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
  V acc = {};
  V p, w;
  int k = 0;
  for (; k + kLanes <= m; k += kLanes) {
    LoadTo(p, psi + k);
    LoadTo(w, s + k);
    acc += w * p * p;
  }
  double rest = 0.0;
  for (; k < m; ++k) rest += s[k] * psi[k] * psi[k];
  return Sum(acc) + rest;
}

// One instruction set's kernels: `Target` is a function attribute (empty for the baseline).
#define MB_GPR_KERNELS(suffix, Target, Vector)                                                              \
  Target double PeriodicSe##suffix(const GprFeatureConstants& k, const double* beta, double x, double xdot, \
                                   double* psi) noexcept {                                                  \
    return psi != nullptr ? PeriodicSeDot<true>(k, beta, x, xdot, psi)                                     \
                          : PeriodicSeDot<false>(k, beta, x, xdot, nullptr);                               \
  }                                                                                                         \
  Target double SeSe##suffix(const GprFeatureConstants& k, const double* beta, double x, double xdot,       \
                             double* psi) noexcept {                                                        \
    return psi != nullptr ? SeSeDot<true>(k, beta, x, xdot, psi) : SeSeDot<false>(k, beta, x, xdot, nullptr); \
  }                                                                                                         \
  Target double QuadraticForm##suffix(const double* c, const double* psi, int m) noexcept {                 \
    return QuadraticFormBody<Vector>(c, psi, m);                                                            \
  }                                                                                                         \
  Target double PackedQuadraticForm##suffix(const GprFeatureLanes* w, const double* psi, int m) noexcept {      \
    return PackedQuadraticFormBody<Vector>(w, psi, m);                                                      \
  }                                                                                                         \
  Target double WeightedSquares##suffix(const double* s, const double* psi, int m) noexcept {               \
    return WeightedSquaresBody<Vector>(s, psi, m);                                                          \
  }                                                                                                         \
  constexpr GprFeatureMap::Kernels kKernels##suffix = {                                                     \
      #suffix, {&PeriodicSe##suffix, &SeSe##suffix}, &QuadraticForm##suffix, &PackedQuadraticForm##suffix,      \
      &WeightedSquares##suffix};

MB_GPR_KERNELS(baseline, , V2)
#ifdef MB_GPR_X86_KERNELS
MB_GPR_KERNELS(avx2_fma, __attribute__((target("avx2,fma"))), V4)
MB_GPR_KERNELS(avx512f, __attribute__((target("avx512f,avx2,fma"))), V8)
#endif
#undef MB_GPR_KERNELS

const GprFeatureMap::Kernels* WidestKernels() noexcept {
#ifdef MB_GPR_X86_KERNELS
  __builtin_cpu_init();  // idempotent; needed if a map is built before the runtime's own initialisation
  if (__builtin_cpu_supports("avx512f")) return &kKernelsavx512f;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return &kKernelsavx2_fma;
#endif
  return &kKernelsbaseline;
}

GprHilbertAxis AxisOf(const HilbertDomain& d) noexcept {
  GprHilbertAxis a;
  a.center = d.center;
  a.half_width = d.half_width;
  a.lower = d.center - d.half_width;
  a.phase_per_unit = kPi / (2.0 * d.half_width);
  a.amplitude = 1.0 / std::sqrt(d.half_width);
  a.count = d.count;
  return a;
}

}  // namespace

GprPackedLowerTriangle::GprPackedLowerTriangle(const Eigen::Ref<const Eigen::MatrixXd>& sigma)
    : size_(static_cast<int>(sigma.rows())) {
  const int padded = (size_ + 7) / 8 * 8;
  std::size_t lanes = 0;
  for (int j0 = 0; j0 < padded; j0 += 8) lanes += static_cast<std::size_t>(padded - j0);
  values_.assign(lanes, GprFeatureLanes{});
  std::size_t block = 0;
  for (int j0 = 0; j0 < padded; j0 += 8) {
    const int groups = (padded - j0) / 8;
    for (int k = 0; k < 8 && j0 + k < size_; ++k) {
      const int column = j0 + k;
      for (int r = column; r < size_; ++r) {
        const double value = r == column ? 0.5 * sigma(r, column) : sigma(r, column);
        const std::size_t index = block + static_cast<std::size_t>(k * groups + (r - j0) / 8);
        values_[index].v[(r - j0) % 8] = value;
      }
    }
    block += static_cast<std::size_t>(8 * groups);
  }
}

GprFeatureMap::GprFeatureMap() noexcept : kernels_(WidestKernels()) {}

GprFeatureMap::GprFeatureMap(const GprBasis& basis) noexcept
    : kind_(basis.kernel == GprKernel::kPeriodicSe ? 0 : 1), kernels_(WidestKernels()) {
  constants_.feature_count = GprFeatureCount(basis);
  constants_.position_count = GprPositionFeatureCount(basis);
  constants_.harmonics = basis.harmonics;
  constants_.inverse_period = 1.0 / basis.period;
  if (basis.kernel == GprKernel::kSeSe) constants_.x_axis = AxisOf(basis.x_domain);
  constants_.xdot_axis = AxisOf(basis.xdot_domain);
}

}  // namespace mb
