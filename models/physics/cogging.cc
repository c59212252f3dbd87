#include "models/physics/cogging.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

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
  return FourierSeries(cos_weight_, sin_weight_, wavenumber_ * x);
}

double CoggingForce::Amplitude(double xdot) const noexcept { return p_.amplitude + p_.amplitude_velocity * std::abs(xdot); }

double CoggingForce::Offset(double xdot) const noexcept {
  return p_.offset + p_.offset_velocity * xdot + p_.offset_velocity_squared * xdot * std::abs(xdot);
}

double CoggingForce::Force(double x, double xdot) const noexcept { return Amplitude(xdot) * Shape(x) + Offset(xdot); }

}  // namespace mb
