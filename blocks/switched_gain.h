#pragma once
// switched_gain: a gain that switches in at a time — a payload picked up mid-record (its mass times the
// acceleration), a tool change, a gain scheduled by time. The added term of a parameter that steps during a record.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = 0 for t < time, y = gain·u for t ≥ time. Ports: in "u", out "y" (direct feedthrough). Parameters: gain (unit of
/// y per unit of u: kg for a payload on the acceleration), time [s]. The switch is a mode in the discrete state frozen
/// between events with a zero crossing t − time, exactly as blocks/step.h (CVODE stops at the switch; fixed-step
/// solvers switch at the end of the step in which it falls). Throws nothing beyond the parameter checks.
class SwitchedGain final : public Block {
 public:
  explicit SwitchedGain(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

 private:
  double gain_;
  double time_;
};

}  // namespace mb
