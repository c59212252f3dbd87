#pragma once
// backlash_load: a load behind a play (gear backlash between a motor and its load), seen from the motor: the
// drive-train benchmark's two-mass model with a dead zone (models/physics/play_coupling.h). While the play is open
// the motor moves its own inertia; once it is taken up the load engages with an impact and rings at the shaft's mode.
// The diagnosed effect `backlash_load` (models/diagnosis/effects/backlash_load.cc) steps the load the same way.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "x" (motor position [m]) and "v" (its velocity [m/s]), out "f" (the force the load needs through the
/// shaft, with the sign of the drive force [N]; on a rotary axis rad, rad/s and N·m). Parameters: mass m_L [kg]
/// (any sign: a fit may pass through zero), frequency_hz f > 0 [Hz] (the engaged shaft's mode √(k/m_L)/2π),
/// damping_ratio ζ > 0 (default 0.05), backlash g ≥ 0 [m] (the play's full width), load_damping β ≥ 0 [1/s] (the
/// load's own viscous friction per unit mass, default 0). Discrete (needs a sampleTime [Ts, offset]): the load's
/// position and velocity are the state, stepped from hit to hit by AdvancePlayLoad (the motor's motion a cubic Hermite
/// between the hits, Runge–Kutta sub-steps); at the first hit the load starts at the motor's position and velocity,
/// centred in the play, and f = 0. Then f = m_L × the shaft's force per unit load mass (AdvancePlayLoad's return).
/// Direct feedthrough from x and v: the output needs this hit's input, so CalcOutput and UpdateDiscrete each advance
/// the load from the last hit (the same arithmetic, the state written by the second only).
/// @throws std::invalid_argument (naming the parameter) for f ≤ 0, ζ ≤ 0, g < 0, β < 0, a non-finite value or no
/// sampleTime.
class BacklashLoad final : public Block {
 public:
  explicit BacklashLoad(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  /// The load's acceleration per unit mass at this hit; its position and velocity after it go to state_out.
  double Step(const BlockContext& context, double state_out[2]) const;
  double mass_, omega_, zeta_, half_gap_, load_damping_, period_;  // [kg], [rad/s], [-], [m], [1/s], Ts [s]
};

}  // namespace mb
