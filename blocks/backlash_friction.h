#pragma once
// backlash_friction: a load coupled through a play (gear, belt, coupling, the nut of a screw) whose friction the motor
// feels only once the play is taken up. After each reversal the motor travels the full gap g before it drives the
// load again (the play operator of Simulink's Backlash block, half-width g/2, on the motor position x): f =
// F_l·s_db(v)·e_g(x), e_g = 1 while the play is taken up, s_db(v) = sign(v) outside the dead band |v| ≤ v_db, else 0.
// The diagnosed effect `backlash` (models/diagnosis/effects/backlash.cc) uses the same law as its regressor.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "x" [m] (motor position), "v" [m/s] (its velocity), out "f" [N] (the load's friction felt through the
/// play, resisting +v). Parameters: gap g > 0 [m] (the full play), load_friction F_l [N], dead_band v_db ≥ 0 [m/s].
/// Discrete (needs a sampleTime): the play's far side p is the discrete state, p ← clamp(p, x − g/2, x + g/2) at
/// each hit, starting at the first hit's x (the play centred). Direct feedthrough from x and v. @throws
/// std::invalid_argument for g ≤ 0, v_db < 0 or no sampleTime.
class BacklashFriction final : public Block {
 public:
  explicit BacklashFriction(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  /// The far side after following x: clamp(p, x − g/2, x + g/2) (x itself before the first hit).
  double FarSide(const BlockContext& context) const;
  double half_gap_, load_friction_, dead_band_;
};

}  // namespace mb
