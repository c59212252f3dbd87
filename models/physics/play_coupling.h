#pragma once
// A load behind a play: the drive-train benchmark's two-mass model with backlash (Nordin & Gutman, "Controlling
// mechanical systems with backlash — a survey", Automatica 38, 2002, §2: the dead-zone model). The motor and the load
// are joined by a shaft of stiffness k and damping c through a play of full width g; while the play is open the shaft
// carries nothing and the motor moves its own inertia only, once it is taken up the load follows with a ring at
// ω = √(k/m_L):
//   δ = x_motor − x_load,  dz(δ) = sign(δ)·max(|δ| − g/2, 0),
//   ẍ_load = ω²·dz(δ) + 2ζω·δ̇·[|δ| > g/2] − β·ẋ_load,   the force on the motor f = m_L·(ẍ_load + β·ẋ_load),
// β = b_L/m_L the load's own viscous friction (its bearings) per unit mass: what settles the load inside the play
// while the motor dwells, and so where it meets the next impact.
// The load is simulated from the motor's motion sampled at its instants (AdvancePlayLoad): the same scheme in the
// backlash_load block (blocks/backlash_load.h) and the diagnosis' effect backlash_load
// (models/diagnosis/effects/backlash_load.cc), so the suggested block adds what the diagnosis fitted.
// Header-only, allocation-free, throws nothing.

#include <algorithm>
#include <cmath>

namespace mb {

/// The play's dead zone: dz(δ) = sign(δ)·max(|δ| − half_gap, 0) [the unit of δ]; half_gap ≥ 0.
inline double DeadZone(double delta, double half_gap) noexcept {
  if (delta > half_gap) return delta - half_gap;
  if (delta < -half_gap) return delta + half_gap;
  return 0.0;
}

/// The shaft's force on the load per unit load mass [m/s² or rad/s²] for the twist δ = x_motor − x_load and its rate
/// δ̇, the play of half width half_gap ≥ 0 (0: the plain two-mass model), ω = 2π f_r [rad/s] of the engaged shaft and
/// its damping ratio ζ. The damper acts only while the play is taken up (no contact, no force).
inline double PlayLoadAcceleration(double delta, double delta_rate, double half_gap, double omega,
                                   double zeta) noexcept {
  const double twist = DeadZone(delta, half_gap);
  const bool engaged = std::abs(delta) > half_gap;
  return omega * omega * twist + (engaged ? 2.0 * zeta * omega * delta_rate : 0.0);
}

/// The load's position and velocity [m, m/s or rad, rad/s].
struct PlayLoad {
  double x = 0.0, v = 0.0;
};

/// The motor's position and velocity at the fraction q ∈ [0, 1] of a step of dt [s] from (x0, v0) to (x1, v1): the
/// cubic Hermite interpolant, which meets both ends' positions and velocities (a straight line between the positions
/// lies inside the curve by a·dt²/8, and the load's twist, a/ω², is that small: at ω = 2π·50 Hz and 1 kHz it was 0.8 %
/// of the force).
inline void HermiteMotor(double x0, double v0, double x1, double v1, double dt, double q, double* x,
                         double* v) noexcept {
  const double q2 = q * q, q3 = q2 * q;
  *x = (2.0 * q3 - 3.0 * q2 + 1.0) * x0 + (q3 - 2.0 * q2 + q) * dt * v0 + (3.0 * q2 - 2.0 * q3) * x1 +
       (q3 - q2) * dt * v1;
  *v = (6.0 * (q2 - q) * (x0 - x1)) / dt + (3.0 * q2 - 4.0 * q + 1.0) * v0 + (3.0 * q2 - 2.0 * q) * v1;
}

/// The number of Runge–Kutta sub-steps AdvancePlayLoad takes over a step of dt [s] at ω [rad/s]: ω·dt/n ≤ 0.3 (a rigid
/// follow within 10⁻⁴), 1 ≤ n ≤ 10 000.
inline int PlaySubSteps(double omega, double dt) noexcept {
  constexpr double kMaxPhasePerStep = 0.3;
  constexpr int kMaxSubSteps = 10000;
  return static_cast<int>(
      std::clamp(std::ceil(omega * dt / kMaxPhasePerStep), 1.0, static_cast<double>(kMaxSubSteps)));
}

/// The motor at the middle and at the end of sub-step j of n over a step of dt (HermiteMotor at q = (j + ½)/n and
/// (j + 1)/n): what AdvancePlayLoad reads, in its order. `mid` and `end` hold a position and a velocity each.
inline void PlayMotorAtSubStep(double x0, double v0, double x1, double v1, double dt, int n, int j, double* mid,
                               double* end) noexcept {
  const double steps = n;
  HermiteMotor(x0, v0, x1, v1, dt, (j + 0.5) / steps, &mid[0], &mid[1]);
  HermiteMotor(x0, v0, x1, v1, dt, (j + 1.0) / steps, &end[0], &end[1]);
}

/// The shape of one load behind the play: its half gap [m or rad], the engaged shaft's damping ratio ζ and the load's
/// own viscous friction per unit mass β [1/s] (the mode ω is the stepper's, shared).
struct PlayLoadShape {
  double half_gap = 0.0, zeta = 0.0, load_damping = 0.0;
};

/// The classical Runge–Kutta method on n sub-steps of h [s] for K loads behind plays on one motor at the mode ω, the
/// motor starting the step at (xa, va) and read at each sub-step's middle and end from motor_at(j, mid, end)
/// (PlayMotorAtSubStep, or the same values stored once for many loads on one motor path: the diagnosis' grid). Each
/// load's arithmetic is K = 1's: K loads step as K separate calls would, to the last bit, their stages computed side by
/// side (one load's stages are a chain the processor must wait along; K of them it overlaps). AdvancePlayLoad's stepper.
template <int K, typename MotorAt>
inline void StepPlayLoads(int n, double h, double xa, double va, const MotorAt& motor_at, double omega,
                          const PlayLoadShape (&shape)[K], PlayLoad (&load)[K]) noexcept {
  // ẍ_L of load k with the motor at (xm, vm) and the load at (xl, vl).
  auto acceleration = [&](int k, double xm, double vm, double xl, double vl) {
    return PlayLoadAcceleration(xm - xl, vm - vl, shape[k].half_gap, omega, shape[k].zeta) - shape[k].load_damping * vl;
  };
  // The motor at the sub-step's start, middle and end: the middle serves two stages, the end the next sub-step's start.
  double mid[2] = {0.0, 0.0}, end[2] = {0.0, 0.0};
  double x[K], v[K], a1[K], a2[K], a3[K], a4[K];
  for (int j = 0; j < n; ++j) {
    motor_at(j, mid, end);
    for (int k = 0; k < K; ++k) {
      x[k] = load[k].x;
      v[k] = load[k].v;
      a1[k] = acceleration(k, xa, va, x[k], v[k]);
    }
    for (int k = 0; k < K; ++k) a2[k] = acceleration(k, mid[0], mid[1], x[k] + 0.5 * h * v[k], v[k] + 0.5 * h * a1[k]);
    for (int k = 0; k < K; ++k) {
      a3[k] = acceleration(k, mid[0], mid[1], x[k] + 0.5 * h * (v[k] + 0.5 * h * a1[k]), v[k] + 0.5 * h * a2[k]);
    }
    for (int k = 0; k < K; ++k) {
      a4[k] = acceleration(k, end[0], end[1], x[k] + h * (v[k] + 0.5 * h * a2[k]), v[k] + h * a3[k]);
    }
    xa = end[0];
    va = end[1];
    for (int k = 0; k < K; ++k) {
      load[k].x = x[k] + h / 6.0 * (v[k] + 2.0 * (v[k] + 0.5 * h * a1[k]) + 2.0 * (v[k] + 0.5 * h * a2[k]) +
                                    (v[k] + h * a3[k]));
      load[k].v = v[k] + h / 6.0 * (a1[k] + 2.0 * a2[k] + 2.0 * a3[k] + a4[k]);
    }
  }
}

/// Advances the load over dt [s] while the motor moves from (x0, v0) to (x1, v1) (HermiteMotor between them): the
/// classical Runge–Kutta method on PlaySubSteps(ω, dt) sub-steps (StepPlayLoads). Semi-implicit Euler at ω·dt/n ≤ 0.02
/// put the load behind the motor by v·dt/(2n), 100 % of a stiff shaft's force at the speed's peak in the block's test.
/// β = load_damping [1/s] ≥ 0 the load's own viscous friction per unit mass.
/// Returns the shaft's force on the load per unit load mass at the end (PlayLoadAcceleration at (x1, v1)): the force on
/// the motor divided by m_L.
inline double AdvancePlayLoad(double x0, double v0, double x1, double v1, double dt, double half_gap, double omega,
                              double zeta, double load_damping, PlayLoad* load) noexcept {
  const int n = PlaySubSteps(omega, dt);
  double xa = 0.0, va = 0.0;
  HermiteMotor(x0, v0, x1, v1, dt, 0.0, &xa, &va);
  const PlayLoadShape shape[1] = {{half_gap, zeta, load_damping}};
  PlayLoad loads[1] = {*load};
  StepPlayLoads(
      n, dt / n, xa, va,
      [&](int j, double* mid, double* end) { PlayMotorAtSubStep(x0, v0, x1, v1, dt, n, j, mid, end); }, omega, shape,
      loads);
  *load = loads[0];
  return PlayLoadAcceleration(x1 - load->x, v1 - load->v, half_gap, omega, zeta);
}

}  // namespace mb
