#pragma once
// rigid_body: a mass on a line with viscous damping, M·ẍ = f − B·ẋ (models/physics/rigid_body.h).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/rigid_body.h"

namespace mb {

/// M·ẍ = f − B·ẋ, x(0) = x0, ẋ(0) = v0. Port: in "f" [N] (no direct feedthrough); outs "x" [m], "v" [m/s].
/// Parameters: mass M [kg] > 0 (default 1), damping B [N·s/m] ≥ 0 (default 0), x0 [m], v0 [m/s] (default 0).
/// States: x, v (continuous).
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
  double x0_;
  double v0_;
};

}  // namespace mb
