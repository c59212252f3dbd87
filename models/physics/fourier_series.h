#pragma once
// The one Fourier-series helper: every harmonic evaluation of the project goes through this header.
//   y(θ) = Σ_{h=1..H} a_h cos(hθ) + b_h sin(hθ)
// Users: the Fourier effect blocks (blocks/position_periodic, velocity_dependent_ripple, time_periodic,
// position_dependent_inertia with the slope), the cogging force (models/physics/cogging.cc), the diagnosis regressors
// (models/diagnosis/effect_regressors.cc) and the weight-space GP's periodic and Hilbert features (models/gpr/basis.cc,
// with four lanes).
// Header-only, no dependency beyond Eigen (and models/gpr/sincos.h, itself header-only): blocks and every models/
// library may include it.

#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "models/gpr/sincos.h"  // header-only, no dependency on mb_gpr

namespace mb {

/// Calls fn(h, cos(hθ), sin(hθ), lane) for h = 1…n, given cos θ and sin θ (the caller chooses how to compute
/// them: std::cos/std::sin, or SinCosBounded in the GP's hot path). The rotation recurrence
///   cos((h+L)θ) = cos(hθ)cos(Lθ) − sin(hθ)sin(Lθ),  sin((h+L)θ) = sin(hθ)cos(Lθ) + cos(hθ)sin(Lθ)
/// runs as `Lanes` independent chains (lane = (h − 1) mod Lanes, stepped by Lθ): Lanes = 1 is the plain
/// recurrence; Lanes = 4 lets the CPU overlap the latency-bound chains (callers may keep one accumulator per
/// lane). Rounding error grows like h·eps. Allocation-free, noexcept if fn is.
template <int Lanes, typename Fn>
inline void ForEachHarmonic(double cos_theta, double sin_theta, int n, Fn&& fn) noexcept {
  static_assert(Lanes >= 1 && Lanes <= 8, "ForEachHarmonic: 1 to 8 lanes");
  double c[static_cast<std::size_t>(Lanes)] = {cos_theta};
  double s[static_cast<std::size_t>(Lanes)] = {sin_theta};
  for (int k = 1; k < Lanes; ++k) {
    c[k] = c[k - 1] * cos_theta - s[k - 1] * sin_theta;
    s[k] = s[k - 1] * cos_theta + c[k - 1] * sin_theta;
  }
  const double c_step = c[Lanes - 1];  // cos(Lθ): each lane steps by `Lanes` harmonics
  const double s_step = s[Lanes - 1];
  int h = 1;
  for (; h + Lanes - 1 <= n; h += Lanes) {
    for (int k = 0; k < Lanes; ++k) {
      fn(h + k, c[k], s[k], k);
      const double c_next = c[k] * c_step - s[k] * s_step;
      s[k] = s[k] * c_step + c[k] * s_step;
      c[k] = c_next;
    }
  }
  for (int k = 0; h <= n; ++h, ++k) fn(h, c[k], s[k], k);
}

/// Calls fn(h, sin(hθ), lane) for h = 1…n, given cos θ and sin θ: the sine-only variant (the GP's Hilbert
/// features). Four lanes, each the Chebyshev three-term recurrence sin((h+4)θ) = 2cos(4θ)·sin(hθ) − sin((h−4)θ),
/// started from sin(−kθ) = −sin(kθ): one multiply and one subtract per harmonic instead of the rotation's four
/// multiplies and two adds. Its rounding error grows like (n/4)²·eps at worst (θ near 0 or π), 2e-13 for n = 160.
template <typename Fn>
inline void ForEachSineHarmonic(double cos_theta, double sin_theta, int n, Fn&& fn) noexcept {
  const double s1 = sin_theta;
  const double c1 = cos_theta;
  const double s2 = 2.0 * s1 * c1;
  const double c2 = 2.0 * c1 * c1 - 1.0;
  const double s3 = s2 * c1 + c2 * s1;
  const double s4 = 2.0 * s2 * c2;
  const double two_c4 = 2.0 * (2.0 * c2 * c2 - 1.0);  // 2cos 4θ
  double previous[4] = {-s3, -s2, -s1, 0.0};  // sin((h − 4)θ)
  double current[4] = {s1, s2, s3, s4};       // sin(hθ)
  int h = 1;
  for (; h + 3 <= n; h += 4) {
    for (int k = 0; k < 4; ++k) {
      fn(h + k, current[k], k);
      const double next = two_c4 * current[k] - previous[k];
      previous[k] = current[k];
      current[k] = next;
    }
  }
  for (int k = 0; h <= n; ++h, ++k) fn(h, current[k], k);
}

/// Σ_h a_h cos(hθ) + b_h sin(hθ), a and b of equal length H: one std::cos/std::sin pair, then the one-lane
/// recurrence over h. Allocation-free.
inline double FourierSeries(const Eigen::Ref<const Eigen::VectorXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b,
                            double theta) noexcept {
  double y = 0.0;
  ForEachHarmonic<1>(std::cos(theta), std::sin(theta), static_cast<int>(a.size()),
                     [&](int h, double c, double s, int) { y += a(h - 1) * c + b(h - 1) * s; });
  return y;
}

/// The design matrix of the series in z: columns g·cos(2πh·z/P), g·sin(2πh·z/P) for h = 1…H
/// (N × 2H, column 2(h−1) the cosine); g = scale (N) when given, else 1. One sin/cos pair per sample, of the phase
/// z/P reduced to [−½, ½] cycle (SinCosBounded), the higher harmonics by the rotation recurrence of ForEachHarmonic,
/// run column by column over all samples at once (rounding error ≈ h·eps, as the blocks' FourierSeries). A
/// least-squares fit of y on it gives the a_h, b_h that FourierSeries(a, b, 2π(z/P)) evaluates. Throws nothing but
/// std::bad_alloc.
inline Eigen::MatrixXd FourierDesignMatrix(const Eigen::Ref<const Eigen::VectorXd>& z, double period, int harmonics,
                                           const Eigen::VectorXd* scale = nullptr) {
  const Eigen::Index n = z.size();
  Eigen::MatrixXd columns(n, 2 * harmonics);
  if (harmonics <= 0) return columns;
  Eigen::ArrayXd c1(n), s1(n);
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  constexpr double kRoundShift = 0x1.8p52;  // adding and subtracting it rounds to nearest (|u| < 2⁵¹)
  for (Eigen::Index i = 0; i < n; ++i) {
    // The phase in cycles reduced to [−½, ½] first, which loses nothing (u minus the nearest integer is exact), so
    // that one bounded sin/cos pair serves: SinCosBounded, within 2·eps of std::sin/std::cos on [−π, π]. A phase of
    // 2⁵¹ cycles or more has no fraction left, and one that is not finite (a period of 0) gives NaN, as std::sin does.
    const double u = z(i) / period;
    if (std::abs(u) < 0x1p51) {
      SinCosBounded(kTwoPi * (u - ((u + kRoundShift) - kRoundShift)), &s1(i), &c1(i));
    } else {
      const double th = kTwoPi * std::remainder(u, 1.0);
      s1(i) = std::sin(th);
      c1(i) = std::cos(th);
    }
  }
  Eigen::ArrayXd c = c1, s = s1, c_next(n);  // cos(hθ), sin(hθ); the next cosine, allocated once
  for (int h = 1; h <= harmonics; ++h) {
    if (scale) {
      columns.col(2 * (h - 1)).array() = scale->array() * c;
      columns.col(2 * (h - 1) + 1).array() = scale->array() * s;
    } else {
      columns.col(2 * (h - 1)).array() = c;
      columns.col(2 * (h - 1) + 1).array() = s;
    }
    if (h == harmonics) break;
    c_next = c * c1 - s * s1;
    s = s * c1 + c * s1;
    c.swap(c_next);
  }
  return columns;
}

/// The coefficient vector `c` of the parameter `name` checked against H harmonics: [] gives H zeros.
/// @throws std::invalid_argument "<name> has <n> entries; give one per harmonic (H) or []".
inline Eigen::VectorXd FourierCoefficients(Eigen::VectorXd c, const std::string& name, int harmonics) {
  if (c.size() == 0) return Eigen::VectorXd::Zero(harmonics);
  if (c.size() != harmonics) {
    throw std::invalid_argument(name + " has " + std::to_string(c.size()) + " entries; give one per harmonic (" +
                                std::to_string(harmonics) + ") or []");
  }
  return c;
}

/// The coefficient parameter `name` of a Fourier block, checked against its parameter "harmonics" (as above).
/// ParameterSet: anything with Vector(name) and Integer(name), i.e. engine/parameters.h's Parameters (a template
/// so that this header needs no engine include).
template <typename ParameterSet>
Eigen::VectorXd FourierCoefficients(const ParameterSet& parameters, const std::string& name) {
  return FourierCoefficients(parameters.Vector(name), name, static_cast<int>(parameters.Integer("harmonics")));
}

/// A Fourier series in position, y(x) = Σ_h a_h cos(hθ) + b_h sin(hθ), θ = 2π(x − x₀)/P: the shape of the
/// position_periodic and velocity_dependent_ripple blocks (period P [m], position offset x₀ [m]).
struct PositionFourierSeries {
  double wavenumber = 0.0;  ///< 2π/P [rad/m]
  double offset = 0.0;      ///< x₀ [m]
  Eigen::VectorXd a, b;     ///< a_h, b_h, h = 1…H
  /// y(x) at position x [m]. Allocation-free.
  double operator()(double x) const noexcept { return FourierSeries(a, b, wavenumber * (x - offset)); }
  /// dy/dx at position x [m] (the unit of y per m): (2π/P)·Σ_h h·(b_h cos(hθ) − a_h sin(hθ)). Allocation-free.
  double Slope(double x) const noexcept {
    const double theta = wavenumber * (x - offset);
    double slope = 0.0;
    ForEachHarmonic<1>(std::cos(theta), std::sin(theta), static_cast<int>(a.size()),
                       [&](int h, double c, double s, int) { slope += h * (b(h - 1) * c - a(h - 1) * s); });
    return wavenumber * slope;
  }
};

/// The series of a block's parameters "period", "position_offset", "harmonics", "cos_coefficients" and
/// "sin_coefficients" (ParameterSet as for FourierCoefficients). @throws as FourierCoefficients.
template <typename ParameterSet>
PositionFourierSeries PositionFourierSeriesOf(const ParameterSet& parameters) {
  return {2.0 * std::numbers::pi / parameters.Number("period"), parameters.Number("position_offset"),
          FourierCoefficients(parameters, "cos_coefficients"), FourierCoefficients(parameters, "sin_coefficients")};
}

}  // namespace mb
