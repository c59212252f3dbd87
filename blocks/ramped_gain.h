#pragma once
// ramped_gain: a gain that ramps in over a time span — a parameter that drifts during a record (the viscous friction
// of a guide whose lubricant warms up), or a gain scheduled by time. The added term of a parameter that drifts.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = gain·ρ(t)·u with ρ(t) = clamp((t − start_time)/(end_time − start_time), 0, 1): 0 before start_time, the full gain
/// from end_time on, linear between. Ports: in "u", out "y" (direct feedthrough). Parameters: gain (unit of y per unit
/// of u: N·s/m for a drift of the viscous friction on the velocity), start_time, end_time [s]. ρ is continuous, so no
/// event is needed. @throws std::invalid_argument (at construction) when end_time ≤ start_time.
class RampedGain final : public Block {
 public:
  explicit RampedGain(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double gain_;
  double start_;
  double end_;
};

}  // namespace mb
