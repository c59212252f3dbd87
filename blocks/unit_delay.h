#pragma once
// unit_delay: y[k] = u[k−1], y[0] = initial_condition (Simulink's Unit Delay, z⁻¹). Discrete; no feedthrough.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y[k] = x[k]; x[k+1] = u[k]; x[0] = initial_condition. Ports: in "u", out "y" (width 1). Requires a
/// sampleTime [Ts, offset]. Output at hit k is the input sampled at hit k−1; it breaks algebraic loops.
class UnitDelay final : public Block {
 public:
  explicit UnitDelay(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  double initial_condition_;
};

}  // namespace mb
