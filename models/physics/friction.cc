#include "models/physics/friction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mb {

namespace {
double Sign(FrictionMode mode) { return static_cast<double>(static_cast<int>(mode)); }
FrictionMode Along(double x) { return x > 0.0 ? FrictionMode::kSlipPositive : FrictionMode::kSlipNegative; }
}  // namespace

void ValidateFrictionParameters(const FrictionParameters& p, const std::string& where) {
  auto check = [&](double value, const char* name, const char* unit) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(where + ": " + name + " must be a finite number >= 0 " + unit + ", got " +
                                  std::to_string(value));
    }
  };
  check(p.viscous, "viscous", "N·s/m");
  check(p.coulomb, "coulomb", "N");
  check(p.breakaway, "static", "N");
  check(p.stribeck_velocity, "stribeck_velocity", "m/s");
  if (p.breakaway < p.coulomb) {
    throw std::invalid_argument(where + ": static (breakaway) force " + std::to_string(p.breakaway) +
                                " N is below the Coulomb force " + std::to_string(p.coulomb) +
                                " N; set static >= coulomb (equal for no stiction)");
  }
}

double StribeckLevel(double coulomb, double breakaway, double stribeck_velocity, double velocity) noexcept {
  if (!(stribeck_velocity > 0.0)) return coulomb;
  // × the reciprocal, not ÷: the division then waits for no velocity, off the solver stage's dependency chain
  // (within 2 ulp of the quotient).
  const double r = velocity * (1.0 / stribeck_velocity);
  const double r2 = r * r;
  // exp(−r²) is exactly 0 in double precision for r² > 745.14: skip glibc's slow underflow path (errno), which
  // a moving stage takes on nearly every call (|v| > 0.14 m/s at v_s = 5 mm/s). Same result, bit for bit.
  if (r2 > 746.0) return coulomb;
  return coulomb + (breakaway - coulomb) * std::exp(-r2);
}

double RegularizedFriction(const FrictionParameters& p, double regularization_velocity, double velocity) noexcept {
  // tanh(a) is exactly ±1 in double for |a| ≥ 22 (glibc returns 1 − tiny there): skip the call, bit-identical.
  const double a = velocity * (1.0 / regularization_velocity);  // × the reciprocal, as in StribeckLevel
  const double sign = std::abs(a) >= 22.0 ? std::copysign(1.0, a) : std::tanh(a);
  return sign *
             StribeckLevel(p.coulomb, p.breakaway, p.stribeck_velocity, velocity) +
         p.viscous * velocity;
}

double SlidingFriction(const FrictionParameters& p, FrictionMode mode, double velocity) noexcept {
  return Sign(mode) * StribeckLevel(p.coulomb, p.breakaway, p.stribeck_velocity, velocity) + p.viscous * velocity;
}

double FrictionForce(const FrictionParameters& p, FrictionMode mode, double velocity,
                     double applied_force) noexcept {
  if (mode == FrictionMode::kStuck) return std::clamp(applied_force, -p.breakaway, p.breakaway);
  return SlidingFriction(p, mode, velocity);
}

FrictionMode NextFrictionMode(const FrictionParameters& p, FrictionMode mode, double velocity,
                              double applied_force, bool stick, double stick_velocity) noexcept {
  if (mode == FrictionMode::kStuck) {
    // ≥, not >: CVODE often returns the located crossing with g = F_s − |f| exactly 0, and the mode must switch
    // there (a zero g is inactive after the restart and would not be reported again).
    if (stick && applied_force != 0.0 && std::abs(applied_force) >= p.breakaway) return Along(applied_force);
    if (std::abs(velocity) > stick_velocity) return Along(velocity);
    return mode;
  }
  if (Sign(mode) * velocity > 0.0) return mode;
  if (stick) return std::abs(applied_force) < p.breakaway ? FrictionMode::kStuck : Along(applied_force);
  return velocity == 0.0 ? mode : Along(velocity);
}

double SteadyStateFriction(const FrictionParameters& p, double velocity) noexcept {
  if (velocity == 0.0) return 0.0;
  return SlidingFriction(p, Along(velocity), velocity);
}

}  // namespace mb
