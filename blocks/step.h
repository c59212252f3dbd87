#pragma once
// step: y = initial for t < time, final for t ≥ time (Simulink's Step). A source with a located discontinuity.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y(t) = initial for t < time, final for t ≥ time. Port: out "y". Parameters: time [s] (default 1),
/// initial, final (defaults 0 and 1, unit free).
/// The output is a function of t alone, so every major step (log time, sample hit) sees the value of its own
/// instant: a discrete block sampling at t = time reads `final`. A zero crossing g = t − time makes CVODE stop
/// at the step (to its root tolerance) and restart from there; fixed-step solvers restart at the end of the
/// integration step that contains it.
class Step final : public Block {
 public:
  explicit Step(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;

 private:
  double time_;
  double initial_;
  double final_;
};

}  // namespace mb
