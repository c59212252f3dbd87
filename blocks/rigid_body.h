#pragma once
// rigid_body: a mass on a line with viscous damping, M·ẍ = f − B·ẋ (models/physics/rigid_body.h), its mass optionally
// scheduled by an input: (M + ΔM)·ẍ = f − B·ẋ, a payload picked up or set down, a mass that varies along the travel.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/rigid_body.h"

namespace mb {

/// M·ẍ = f − B·ẋ, x(0) = x0, ẋ(0) = v0. Port: in "f" [N] (no direct feedthrough); outs "x" [m], "v" [m/s].
/// Parameters: mass M [kg] > 0 (default 1), damping B [N·s/m] ≥ 0 (default 0), x0 [m], v0 [m/s] (default 0),
/// mass_input (default false): with true, a second input "added_mass" ΔM [kg] (no direct feedthrough) adds to M,
/// (M + ΔM)·ẍ = f − B·ẋ — what a mass of time or of the position is in a simulated loop, where a force ΔM·ẍ read from
/// the body's own acceleration would close an algebraic loop (the diagnosis' mass effects in simulation mode,
/// tools/workflow/suggest.cc). The total is held at 0.1 % of M or more (a refit's trial may ask for less; no body
/// loses its own mass). States: x, v (continuous).
/// No acceleration output, on purpose: a = (f − B v)/M depends on f at the same instant, and the engine's
/// feedthrough is per input port, so an "a" port would make f feed through and turn every feedback loop around
/// the body (PD on x and v) into an algebraic loop. Form a with a sum and a gain where it is needed, or
/// differentiate v (as Simulink models do).
class RigidBody final : public Block {
 public:
  explicit RigidBody(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;

 private:
  RigidBodyParameters body_;
  bool mass_input_;
  double x0_;
  double v0_;
};

}  // namespace mb
