#include "models/gpr/feature_map.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numbers>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MB_GPR_X86_KERNELS 1
#endif

namespace mb {
namespace {

// GCC/Clang vector extensions: the compiler maps them onto the registers of each function's target
// (4 SSE2 registers for V8 in the baseline kernels, 2 AVX2 registers, 1 AVX-512 register).
using V2 = double __attribute__((vector_size(16)));
using V4 = double __attribute__((vector_size(32)));
using V8 = double __attribute__((vector_size(64)));

// 1/n! (exact to round-off: n! is exact in a double up to 18!, beyond that its rounding is far below the terms').
constexpr double InverseFactorial(int n) noexcept {
  double f = 1.0;
  for (int i = 2; i <= n; ++i) f *= i;
  return 1.0 / f;
}
// The Taylor coefficients of sin r − r in powers of r: kSinTaylor[k] = (−1)ᵏ/(2k+1)!, k = 1…10.
constexpr double kSinTaylor[11] = {
    1.0,
    -InverseFactorial(3),  InverseFactorial(5),  -InverseFactorial(7),  InverseFactorial(9),
    -InverseFactorial(11), InverseFactorial(13), -InverseFactorial(15), InverseFactorial(17),
    -InverseFactorial(19), InverseFactorial(21)};

// The lanes of the first block of features: a Hilbert axis' harmonics 1…8; the periodic pairs' harmonics 1…4,
// each as cos (a quarter turn more) then sin; the periodic harmonics −3…0 from them.
constexpr V8 kLaneHarmonics = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0};
constexpr V8 kPairHarmonics = {1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0};
constexpr V8 kCosineLanes = {1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0};
constexpr V8 kOneZero = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0};
constexpr V8 kConjugate = {1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, 1.0};
constexpr V8 kLaneIndex = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0};

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

// The sine of a quarter-turn count, lane by lane: sin(q·π/2) for |q| < 2⁵¹. q is reduced to f = q − 2n ∈ [−1, 1]
// (n = round(q/2), by the 1.5·2⁵² shift; exact), so that sin(q·π/2) = (−1)ⁿ sin(f·π/2), and sin r for
// |r| = |f·π/2| ≤ π/2 is its Taylor polynomial to r²¹ (truncation below 1.3e-18), evaluated by Estrin's scheme in
// z = r²: a few ulp at most, no libm call; tests/gpr/feature_map_test.cc compares every feature with libm.
// (Out-parameters here and below: a vector returned or passed by value changes the ABI between targets.)
[[gnu::always_inline]] inline void SinQuarterTurns(const V8& q, V8& sine) noexcept {
  using V = V8;
  using Bits = std::uint64_t __attribute__((vector_size(64)));
  constexpr double kShift = 0x1.8p52;
  const V shifted = q * 0.5 + kShift;  // round(q/2) in the low mantissa bits
  const V n = shifted - kShift;
  const V r = (q - 2.0 * n) * (0.5 * std::numbers::pi);
  const V z = r * r;
  const V z2 = z * z;
  const V z4 = z2 * z2;
  const V z8 = z4 * z4;
  // p(z) = Σ_{k=1..10} (−1)ᵏ z^{k−1}/(2k+1)!, so that sin r = r + r·z·p(z).
  const V p01 = kSinTaylor[1] + kSinTaylor[2] * z;
  const V p23 = kSinTaylor[3] + kSinTaylor[4] * z;
  const V p45 = kSinTaylor[5] + kSinTaylor[6] * z;
  const V p67 = kSinTaylor[7] + kSinTaylor[8] * z;
  const V p89 = kSinTaylor[9] + kSinTaylor[10] * z;
  const V p = (p01 + z2 * p23) + z4 * (p45 + z2 * p67) + z8 * p89;
  const Bits sign = (__builtin_bit_cast(Bits, shifted) & 1U) << 63;  // n odd: −sin
  sine = __builtin_bit_cast(V, __builtin_bit_cast(Bits, r + (r * z) * p) ^ sign);
}

// The weights of lanes lane…lane+7 of a block of `count`: kPadded reads GprPackedWeights' zero-padded copy; else
// the caller's β, whose last partial block is copied to the stack after zeros (the same lanes, so the same bits).
template <bool kPadded>
[[gnu::always_inline]] inline void LoadWeights(V8& w, const double* block, int lane, int count) noexcept {
  if (kPadded || lane + 8 <= count) {
    LoadTo(w, block + lane);
    return;
  }
  alignas(64) double tail[8] = {};
  for (int k = 0; lane + k < count; ++k) tail[k] = block[lane + k];
  LoadTo(w, tail);
}

// Writes the first min(n, 8) lanes of v to p.
[[gnu::always_inline]] inline void StoreLanes(double* p, const V8& v, int n) noexcept {
  if (n >= 8) {
    Store(p, v);
    return;
  }
  for (int k = 0; k < n; ++k) p[k] = v[k];
}

// One block of features f_j, j = 0…count−1, that satisfy f_{j+8} = two_cos·f_j − f_{j−8} lane by lane (the
// Chebyshev recurrence of sines and cosines of multiples of one angle): `first` holds f_0…f_7, `before_first`
// f_{−8}…f_{−1}. Adds the lanes of Σ_j w_j f_j to acc; with kStore also writes f to psi.
template <bool kPadded, bool kStore>
[[gnu::always_inline]] inline void RecurrenceDot(const V8& first, const V8& before_first, double two_cos,
                                                 const double* weights, int count, double* psi, V8& acc) noexcept {
  V8 current = first;
  V8 previous = before_first;
  for (int j = 0; j < count; j += 8) {
    V8 w;
    LoadWeights<kPadded>(w, weights, j, count);
    acc += w * current;
    if constexpr (kStore) StoreLanes(psi + j, current, count - j);
    const V8 next = two_cos * current - previous;
    previous = current;
    current = next;
  }
}

// A Hilbert axis: ψ_j(u) = amplitude·sin(jθ), θ = q·π/2 with q = (u − lower)/L ∈ [0, 2] inside the domain. Eight
// lanes of sin(jθ), j = 1…8, evaluated directly, then the recurrence in 8θ (2cos 8θ = 2 − 4 sin² 4θ). Outside the
// domain the amplitude is 0 (q clamped so that the sines stay finite): no branch.
template <bool kPadded, bool kStore>
[[gnu::always_inline]] inline void HilbertDot(const GprHilbertAxis& a, double u, const double* weights, double* psi,
                                              V8& acc) noexcept {
  const double q = std::clamp((u - a.lower) * a.quarter_turns_per_unit, 0.0, 2.0);
  const double amplitude = std::abs(u - a.center) <= a.half_width ? a.amplitude : 0.0;
  V8 sines;
  SinQuarterTurns(q * kLaneHarmonics, sines);
  const double two_cos = 2.0 - 4.0 * (sines[3] * sines[3]);
  const V8 current = sines * amplitude;
  const V8 previous = -__builtin_shufflevector(current, V8{}, 6, 5, 4, 3, 2, 1, 0, 8);  // −sin((8 − j)θ)
  RecurrenceDot<kPadded, kStore>(current, previous, two_cos, weights, a.count, psi, acc);
}

// The periodic features of x: lanes [cos jθ, sin jθ, …, cos (j+3)θ, sin (j+3)θ], θ = 2π·frac(x/τ); the first
// four harmonics directly (cos = sin of a quarter turn more), then the recurrence in 4θ over 2J lanes.
template <bool kPadded, bool kStore>
[[gnu::always_inline]] inline void PeriodicDot(const GprFeatureConstants& k, double x, const double* weights,
                                               double* psi, V8& acc) noexcept {
  constexpr double kShift = 0x1.8p52;
  const double t = x * k.inverse_period;
  const double turn = std::abs(t) < 0x1p51 ? t - ((t + kShift) - kShift) : 0.0;  // ∈ [−½, ½]
  V8 current;
  SinQuarterTurns((4.0 * turn) * kPairHarmonics + kCosineLanes, current);
  // Harmonics −3…0: [cos 3θ, −sin 3θ, cos 2θ, −sin 2θ, cos θ, −sin θ, 1, 0].
  const V8 previous = __builtin_shufflevector(current, kOneZero, 4, 5, 2, 3, 0, 1, 14, 15) * kConjugate;
  RecurrenceDot<kPadded, kStore>(current, previous, 2.0 * current[6], weights, 2 * k.harmonics, psi, acc);
}

// "PS": ψ = [1, cos ωx, sin ωx, …, cos Jωx, sin Jωx | Hilbert features of ẋ], ωx = 2π·frac(x/τ).
template <bool kPadded, bool kStore>
[[gnu::always_inline]] inline double PeriodicSeDot(const GprFeatureConstants& k, const GprWeightBlocks& w, double x,
                                                   double xdot, double* psi) noexcept {
  if constexpr (kStore) psi[0] = 1.0;
  V8 position = {};
  V8 velocity = {};
  PeriodicDot<kPadded, kStore>(k, x, w.position, kStore ? psi + 1 : nullptr, position);
  HilbertDot<kPadded, kStore>(k.xdot_axis, xdot, w.velocity, kStore ? psi + k.position_count : nullptr, velocity);
  return w.constant + Sum(position + velocity);
}

// "DS": ψ = [Hilbert features of x | Hilbert features of ẋ].
template <bool kPadded, bool kStore>
[[gnu::always_inline]] inline double SeSeDot(const GprFeatureConstants& k, const GprWeightBlocks& w, double x,
                                             double xdot, double* psi) noexcept {
  V8 position = {};
  V8 velocity = {};
  HilbertDot<kPadded, kStore>(k.x_axis, x, w.position, psi, position);
  HilbertDot<kPadded, kStore>(k.xdot_axis, xdot, w.velocity, kStore ? psi + k.position_count : nullptr, velocity);
  return w.constant + Sum(position + velocity);
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

// Σ_{d=0}^{8·blocks−1} A_d cos dθ, θ = q·π/2, for the zero-padded coefficients A: cos dθ and sin dθ for d = 0…7
// directly, then rotations by 8θ (angle addition: the error grows linearly in d, not quadratically as the
// three-term recurrence's).
[[gnu::always_inline]] inline double CosineSeries(const double* a, int blocks, double q) noexcept {
  V8 cosines;
  V8 sines;
  SinQuarterTurns(q * kLaneIndex + 1.0, cosines);
  SinQuarterTurns(q * kLaneIndex, sines);
  const double cos_step = 1.0 - 2.0 * (sines[4] * sines[4]);  // cos 8θ
  const double sin_step = 2.0 * (sines[4] * cosines[4]);      // sin 8θ
  V8 acc = {};
  for (int b = 0; b < blocks; ++b) {
    V8 w;
    LoadTo(w, a + 8 * b);
    acc += w * cosines;
    const V8 next = cosines * cos_step - sines * sin_step;
    sines = sines * cos_step + cosines * sin_step;
    cosines = next;
  }
  return Sum(acc);
}

// ψ_xᵀ Σ_xẋ ψ_ẋ from the m_ẋ columns of Σ_xẋ, each `blocks` blocks of eight rows (zero-padded): four columns at a
// time, ψ_x loaded once per block of rows. ψ_x is read in whole blocks (its lanes beyond m_x meet zero rows).
template <typename V>
[[gnu::always_inline]] inline double CrossTerm(const double* columns, int blocks, const double* psi_x,
                                               const double* psi_xdot, int count) noexcept {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
  const std::ptrdiff_t stride = 8 * blocks;
  V total = {};
  int k = 0;
  V p;
  for (; k + 4 <= count; k += 4) {
    const double* c0 = columns + k * stride;
    V a0 = {}, a1 = {}, a2 = {}, a3 = {};
    for (int i = 0; i < stride; i += kLanes) {
      LoadTo(p, psi_x + i);
      MultiplyAdd(a0, c0 + i, p);
      MultiplyAdd(a1, c0 + stride + i, p);
      MultiplyAdd(a2, c0 + 2 * stride + i, p);
      MultiplyAdd(a3, c0 + 3 * stride + i, p);
    }
    total += (a0 * psi_xdot[k] + a1 * psi_xdot[k + 1]) + (a2 * psi_xdot[k + 2] + a3 * psi_xdot[k + 3]);
  }
  for (; k < count; ++k) {
    const double* c0 = columns + k * stride;
    V a0 = {};
    for (int i = 0; i < stride; i += kLanes) {
      LoadTo(p, psi_x + i);
      MultiplyAdd(a0, c0 + i, p);
    }
    total += a0 * psi_xdot[k];
  }
  return Sum(total);
}

// ψᵀΣψ for "DS" from GprSeriesCovariance (see there); psi holds ψ with zeros in [M, M₈).
template <typename V>
[[gnu::always_inline]] inline double SeriesQuadraticFormBody(const GprFeatureConstants& k,
                                                             const GprSeriesCovarianceView& s, double x,
                                                             double xdot, const double* psi) noexcept {
  const GprHilbertAxis& ax = k.x_axis;
  const GprHilbertAxis& av = k.xdot_axis;
  const double qx = std::clamp((x - ax.lower) * ax.quarter_turns_per_unit, 0.0, 2.0);
  const double qv = std::clamp((xdot - av.lower) * av.quarter_turns_per_unit, 0.0, 2.0);
  const double inside_x = std::abs(x - ax.center) <= ax.half_width ? 1.0 : 0.0;
  const double inside_v = std::abs(xdot - av.center) <= av.half_width ? 1.0 : 0.0;
  const double xx = CosineSeries(s.x_series, s.x_series_blocks, qx);
  const double vv = CosineSeries(s.xdot_series, s.xdot_series_blocks, qv);
  const double xv = CrossTerm<V>(s.cross, s.cross_blocks, psi, psi + k.position_count, av.count);
  return (inside_x * xx + inside_v * vv) + 2.0 * xv;
}

// One instruction set's kernels: `Target` is a function attribute (empty for the baseline).
#define MB_GPR_KERNELS(suffix, Target, Vector)                                                              \
  template <bool kPadded>                                                                                   \
  Target double PeriodicSe##suffix(const GprFeatureConstants& k, const GprWeightBlocks& w, double x,        \
                                   double xdot, double* psi) noexcept {                                     \
    return psi != nullptr ? PeriodicSeDot<kPadded, true>(k, w, x, xdot, psi)                               \
                          : PeriodicSeDot<kPadded, false>(k, w, x, xdot, nullptr);                         \
  }                                                                                                         \
  template <bool kPadded>                                                                                   \
  Target double SeSe##suffix(const GprFeatureConstants& k, const GprWeightBlocks& w, double x, double xdot, \
                             double* psi) noexcept {                                                        \
    return psi != nullptr ? SeSeDot<kPadded, true>(k, w, x, xdot, psi)                                     \
                          : SeSeDot<kPadded, false>(k, w, x, xdot, nullptr);                               \
  }                                                                                                         \
  Target double QuadraticForm##suffix(const double* c, const double* psi, int m) noexcept {                 \
    return QuadraticFormBody<Vector>(c, psi, m);                                                            \
  }                                                                                                         \
  Target double PackedQuadraticForm##suffix(const GprFeatureLanes* w, const double* psi, int m) noexcept {  \
    return PackedQuadraticFormBody<Vector>(w, psi, m);                                                      \
  }                                                                                                         \
  Target double WeightedSquares##suffix(const double* s, const double* psi, int m) noexcept {               \
    return WeightedSquaresBody<Vector>(s, psi, m);                                                          \
  }                                                                                                         \
  Target double SeriesQuadraticForm##suffix(const GprFeatureConstants& k, const GprSeriesCovarianceView& s,  \
                                            double x, double xdot, const double* psi) noexcept {            \
    return SeriesQuadraticFormBody<Vector>(k, s, x, xdot, psi);                                             \
  }                                                                                                         \
  constexpr GprFeatureMap::Kernels kKernels##suffix = {                                                     \
      #suffix,                                                                                              \
      {{&PeriodicSe##suffix<false>, &PeriodicSe##suffix<true>}, {&SeSe##suffix<false>, &SeSe##suffix<true>}}, \
      &QuadraticForm##suffix,                                                                               \
      &PackedQuadraticForm##suffix,                                                                         \
      &WeightedSquares##suffix,                                                                             \
      &SeriesQuadraticForm##suffix};

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

bool Supported(const GprFeatureMap::Kernels* kernels) noexcept {
#ifdef MB_GPR_X86_KERNELS
  __builtin_cpu_init();
  if (kernels == &kKernelsavx512f) return __builtin_cpu_supports("avx512f");
  if (kernels == &kKernelsavx2_fma) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
  return kernels == &kKernelsbaseline;
}

GprHilbertAxis AxisOf(const HilbertDomain& d) noexcept {
  GprHilbertAxis a;
  a.center = d.center;
  a.half_width = d.half_width;
  a.lower = d.center - d.half_width;
  a.quarter_turns_per_unit = 1.0 / d.half_width;
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

bool GprFeatureMap::UseInstructionSet(std::string_view name) noexcept {
  const Kernels* const all[] = {
      &kKernelsbaseline,
#ifdef MB_GPR_X86_KERNELS
      &kKernelsavx2_fma, &kKernelsavx512f,
#endif
  };
  for (const Kernels* kernels : all) {
    if (name == kernels->name && Supported(kernels)) {
      kernels_ = kernels;
      return true;
    }
  }
  return false;
}

GprFeatureMap::GprFeatureMap(const GprBasis& basis) noexcept
    : kind_(basis.kernel == GprKernel::kPeriodicSe ? 0 : 1), kernels_(WidestKernels()) {
  constants_.feature_count = GprFeatureCount(basis);
  constants_.position_count = GprPositionFeatureCount(basis);
  constants_.constant_count = basis.kernel == GprKernel::kPeriodicSe ? 1 : 0;
  constants_.harmonics = basis.harmonics;
  constants_.inverse_period = 1.0 / basis.period;
  if (basis.kernel == GprKernel::kSeSe) constants_.x_axis = AxisOf(basis.x_domain);
  constants_.xdot_axis = AxisOf(basis.xdot_domain);
}

GprPackedWeights::GprPackedWeights(const GprFeatureConstants& k, const double* beta) {
  const int position = k.position_count - k.constant_count;
  const int velocity = k.feature_count - k.position_count;
  velocity_block_ = static_cast<std::size_t>((position + 7) / 8);
  lanes_.assign(velocity_block_ + static_cast<std::size_t>((velocity + 7) / 8), GprFeatureLanes{});
  for (int j = 0; j < position; ++j) {
    lanes_[static_cast<std::size_t>(j / 8)].v[j % 8] = beta[k.constant_count + j];
  }
  for (int j = 0; j < velocity; ++j) {
    lanes_[velocity_block_ + static_cast<std::size_t>(j / 8)].v[j % 8] = beta[k.position_count + j];
  }
  constant_ = k.constant_count > 0 ? beta[0] : 0.0;
}

GprSeriesCovariance::GprSeriesCovariance(const GprFeatureConstants& k,
                                         const Eigen::Ref<const Eigen::MatrixXd>& sigma) {
  const int mx = k.x_axis.count;
  const int mv = k.xdot_axis.count;
  // A_d = (a²/2)(Σ_{|j−k|=d} Σ_jk − Σ_{j+k=d} Σ_jk) of one diagonal block (features j, k = 1…m at `offset`).
  const auto series = [&sigma](int offset, int m, double amplitude, std::vector<GprFeatureLanes>* out) {
    std::vector<double> a(static_cast<std::size_t>(2 * m + 1), 0.0);
    for (int j = 1; j <= m; ++j) {
      for (int i = 1; i <= m; ++i) {
        const double value = sigma(offset + std::max(i, j) - 1, offset + std::min(i, j) - 1);  // lower triangle
        a[static_cast<std::size_t>(std::abs(i - j))] += value;
        a[static_cast<std::size_t>(i + j)] -= value;
      }
    }
    out->assign(static_cast<std::size_t>((2 * m + 1 + 7) / 8), GprFeatureLanes{});
    for (std::size_t d = 0; d < a.size(); ++d) (*out)[d / 8].v[d % 8] = 0.5 * amplitude * amplitude * a[d];
  };
  series(0, mx, k.x_axis.amplitude, &x_series_);
  series(mx, mv, k.xdot_axis.amplitude, &xdot_series_);
  cross_blocks_ = (mx + 7) / 8;
  cross_.assign(static_cast<std::size_t>(mv * cross_blocks_), GprFeatureLanes{});
  for (int c = 0; c < mv; ++c) {
    for (int r = 0; r < mx; ++r) {
      cross_[static_cast<std::size_t>(c * cross_blocks_ + r / 8)].v[r % 8] = sigma(mx + c, r);  // lower triangle
    }
  }
}

}  // namespace mb
