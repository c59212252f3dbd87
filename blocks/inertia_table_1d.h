#pragma once
// inertia_table_1d: the force of a moving mass that varies with the position, its variation M(x) a table of the
// position (blocks/lookup_table_1d.h's interpolation) — a load over one stretch of the travel (a clamp, a cable
// carrier's loop, a second carriage coupled there), a mass that grows along the travel (a counterweight's chain
// paying out). With the kinetic energy T = ½M(x)·v², Lagrange's equation d/dt(∂T/∂v) − ∂T/∂x gives
//   y = g·(M(x)·a + ½M′(x)·v²)
// (Goldstein, Classical Mechanics, 3rd ed., §1.4), M′ the slope of the table's segment holding x. The periodic
// variation is position_dependent_inertia (blocks/position_dependent_inertia.h). The diagnosis' local_inertia and
// inertia_along_travel (models/diagnosis/effects/factor_products.cc: acceleration × position_local / position_smooth)
// add it; its table is usually fitted.

#include "blocks/lookup_table_1d.h"
#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "x" [m], in "v" [m/s], in "a" [m/s²]; out "y" [N], out "mass" g·M(x) [kg]. Parameters: breakpoints
/// x_1 < … < x_n [m] (n ≥ 2), table M_1 … M_n [kg] (the mass's variation; the constant part is the model's mass),
/// extrapolation "clip" (default: M holds its end values and M′ is 0 beyond the breakpoints) or "linear", gain g
/// (default 1) scaling both outputs, acceleration_input (default true; false: no input "a" and y = g·½M′(x)·v² — in a
/// simulated loop the plant takes g·M(x) from "mass" on its mass input, blocks/rigid_body.h).
/// Inherited sample time; x, v and a feed through.
/// @throws std::invalid_argument as lookup_table_1d (LinearTable), each message saying how to fix it.
class InertiaTable1d final : public Block {
 public:
  explicit InertiaTable1d(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  LinearTable mass_;  ///< M(x) [kg]
  double gain_ = 1.0;  ///< g
  bool acceleration_input_ = true;
};

}  // namespace mb
