#pragma once
// switched_gain: a gain that switches in at a time, and out again at a later one when given — a payload picked up
// mid-record (its mass times the acceleration) and set down, a tool change, a clamp, a gain scheduled by time. The added
// term of a parameter that steps during a record, or is there for a while.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = gain·u for time ≤ t < off_time, else 0. Ports: in "u", out "y" (direct feedthrough). Parameters: gain (unit of
/// y per unit of u: kg for a payload on the acceleration), time [s], off_time [s] (default 1e300: never). Each switch
/// is a mode in the discrete state frozen between events with a zero crossing, t − time and t − off_time, exactly as
/// blocks/step.h (CVODE stops at the switch; fixed-step solvers switch at the end of the step in which it falls).
/// Throws std::invalid_argument when off_time is not after time, nothing else beyond the parameter checks.
class SwitchedGain final : public Block {
 public:
  explicit SwitchedGain(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

 private:
  double Mode(double t) const { return t - time_ >= 0.0 && t - off_time_ < 0.0 ? 1.0 : 0.0; }
  double gain_;
  double time_;
  double off_time_;
};

}  // namespace mb
