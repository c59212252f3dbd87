#include "models/physics/resonance.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mb {

StructuralResonance::StructuralResonance(ResonanceParameters parameters) : p_(parameters) {
  if (!std::isfinite(p_.frequency_hz) || !std::isfinite(p_.damping_ratio) || !std::isfinite(p_.modal_gain)) {
    throw std::invalid_argument("resonance: all parameters must be finite");
  }
  if (p_.damping_ratio < 0.0) throw std::invalid_argument("resonance: damping_ratio must be ≥ 0");
  if (p_.modal_gain != 0.0 && !(p_.frequency_hz > 0.0)) {
    throw std::invalid_argument("resonance: frequency_hz must be > 0 Hz when modal_gain ≠ 0");
  }
  omega_ = 2.0 * std::numbers::pi * p_.frequency_hz;
}

double StructuralResonance::ModalAcceleration(double q, double qdot, double specific_force) const noexcept {
  return p_.modal_gain * specific_force - 2.0 * p_.damping_ratio * omega_ * qdot - omega_ * omega_ * q;
}

}  // namespace mb
