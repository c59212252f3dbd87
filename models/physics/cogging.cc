#include "models/physics/cogging.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "models/gpr/sincos.h"  // header-only, no dependency on mb_gpr
#include "models/physics/fourier_series.h"

namespace mb {

CoggingForce::CoggingForce(CoggingParameters parameters) : p_(std::move(parameters)) {
  if (!(p_.pole_pitch > 0.0) || !std::isfinite(p_.pole_pitch)) {
    throw std::invalid_argument("cogging: pole_pitch must be a positive length in m");
  }
  if (p_.harmonics.size() == 0 || p_.harmonics.size() != p_.phases.size()) {
    throw std::invalid_argument("cogging: give one phase per harmonic (" + std::to_string(p_.harmonics.size()) +
                                " harmonics, " + std::to_string(p_.phases.size()) + " phases)");
  }
  if (!p_.harmonics.allFinite() || !p_.phases.allFinite() || !std::isfinite(p_.amplitude) ||
      !std::isfinite(p_.amplitude_velocity) || !std::isfinite(p_.offset) || !std::isfinite(p_.offset_velocity) ||
      !std::isfinite(p_.offset_velocity_squared)) {
    throw std::invalid_argument("cogging: all parameters must be finite");
  }
  wavenumber_ = 2.0 * std::numbers::pi / p_.pole_pitch;
  sin_weight_ = p_.harmonics.array() * p_.phases.array().cos();
  cos_weight_ = p_.harmonics.array() * p_.phases.array().sin();
}

double CoggingForce::Shape(double x) const noexcept {
  // FourierSeries' sum, with SinCosBounded (a third of std::sin/std::cos's cost) for |θ| ≤ 2048 rad (±7.3 m at
  // τ = 22.5 mm): the plant's hot path, once per derivative evaluation. Its Cody–Waite reduction stays exact
  // there (n·(π/2)_hi exact for n < 2²⁰); measured within 1 eps of std::sin/std::cos on 2·10⁷ angles in
  // ±2048 rad, as within its specified ±kSinCosMaxAngle. Farther out, std::sin/std::cos.
  constexpr double kMaxAngle = 2048.0;
  const double theta = wavenumber_ * x;
  double s1, c1;
  if (std::abs(theta) <= kMaxAngle) {
    SinCosBounded(theta, &s1, &c1);
  } else {
    s1 = std::sin(theta);
    c1 = std::cos(theta);
  }
  const double* a = cos_weight_.data();
  const double* b = sin_weight_.data();
  double y = 0.0;
  ForEachHarmonic<1>(c1, s1, static_cast<int>(cos_weight_.size()),
                     [&](int h, double c, double s, int) { y += a[h - 1] * c + b[h - 1] * s; });
  return y;
}

}  // namespace mb
