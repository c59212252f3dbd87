#include "models/physics/stribeck.h"

#include <cmath>
#include <stdexcept>

#include "models/physics/friction.h"

namespace mb {

StribeckFriction::StribeckFriction(StribeckParameters parameters) : p_(parameters) {
  if (!(p_.coulomb >= 0.0) || !(p_.static_friction >= 0.0)) {
    throw std::invalid_argument("friction: coulomb and static_friction must be ≥ 0 N");
  }
  if (!(p_.stribeck_velocity > 0.0) || !(p_.regularization_velocity > 0.0)) {
    throw std::invalid_argument("friction: stribeck_velocity and regularization_velocity must be > 0 m/s");
  }
  if (!std::isfinite(p_.coulomb) || !std::isfinite(p_.static_friction) || !std::isfinite(p_.viscous_squared) ||
      !std::isfinite(p_.stribeck_velocity) || !std::isfinite(p_.regularization_velocity)) {
    throw std::invalid_argument("friction: all parameters must be finite");
  }
}

double StribeckFriction::Force(double xdot) const noexcept {
  const FrictionParameters law{0.0, p_.coulomb, p_.static_friction, p_.stribeck_velocity};
  return RegularizedFriction(law, p_.regularization_velocity, xdot) + p_.viscous_squared * xdot * std::abs(xdot);
}

}  // namespace mb
