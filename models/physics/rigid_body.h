#pragma once
// Rigid body on a line (the moving part of a linear motor without cogging, payload or resonance):
//   M·ẍ = f − B·ẋ.
// Shared by the rigid_body block and the plant models; header-only, no engine dependency.
// Source: any mechanics text; the paper's nominal plant P_n = 1/(M_n s² + B_n s) (eq. 4, DESIGN.md) is this
// model's transfer function from f to x.

#include <stdexcept>
#include <string>

namespace mb {

/// Mass and viscous damping of a body moving on one axis.
struct RigidBodyParameters {
  double mass = 1.0;     ///< M [kg], > 0
  double damping = 0.0;  ///< B [N·s/m], ≥ 0 (viscous friction of bearings, back-EMF of an amplifier in
                         ///< current mode, …)
};

/// Throws std::invalid_argument (prefixed by `where`, e.g. the block name) unless M > 0 and finite and B ≥ 0 and
/// finite.
inline void ValidateRigidBodyParameters(const RigidBodyParameters& p, const std::string& where) {
  if (!(p.mass > 0.0) || p.mass > 1e300) {
    throw std::invalid_argument(where + ": mass must be a positive, finite number of kg, got " +
                                std::to_string(p.mass));
  }
  if (!(p.damping >= 0.0) || p.damping > 1e300) {
    throw std::invalid_argument(where + ": damping must be a finite number >= 0 N·s/m, got " +
                                std::to_string(p.damping));
  }
}

/// Acceleration a = (f − B·v)/M [m/s²] for a force f [N] at velocity v [m/s].
inline double RigidBodyAcceleration(const RigidBodyParameters& p, double force, double velocity) noexcept {
  return (force - p.damping * velocity) / p.mass;
}

}  // namespace mb
