#pragma once
// ramped_gain: a gain that ramps in over a time span — a parameter that drifts during a record (the viscous friction
// of a guide whose lubricant warms up), or a gain scheduled by time. The added term of a parameter that drifts
// linearly (shape "linear") or settles as a first-order warm-up (shape "exponential").

#include <string>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = gain·ρ(t)·u. Shape "linear" (default): ρ(t) = clamp((t − start_time)/(end_time − start_time), 0, 1) — 0 before
/// start_time, the full gain from end_time on, linear between. Shape "exponential": ρ(t) = 1 − exp(−(t −
/// start_time)/time_constant) from start_time on, 0 before — a first-order lag's step response (a lubricant warming
/// with a thermal time constant), 63 % of the gain at start_time + time_constant, the full gain as t → ∞; end_time is
/// not used. Ports: in "u", out "y" (direct feedthrough). Parameters: gain (unit of y per unit of u: N·s/m for a drift
/// of the viscous friction on the velocity), start_time, end_time, time_constant [s], shape. ρ is continuous, so no
/// event is needed (the exponential's kink at start_time is one of slope only). Simulink: a Clock into a 1-D Lookup
/// Table (linear) or into Fcn 1 − exp(−(u − t_s)/T), times u in a Product. @throws std::invalid_argument (at
/// construction) when shape is "linear" and end_time ≤ start_time, or "exponential" and time_constant ≤ 0.
class RampedGain final : public Block {
 public:
  explicit RampedGain(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double gain_;
  double start_;
  double end_;
  double time_constant_;
  bool exponential_;
};

}  // namespace mb
