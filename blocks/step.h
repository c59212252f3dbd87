#pragma once
// step: y = initial for t < time, final for t ≥ time (Simulink's Step). A source with a located discontinuity.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y(t) = initial for t < time, final for t ≥ time. Port: out "y". Parameters: time [s] (default 1),
/// initial, final (defaults 0 and 1, unit free).
/// The switch is a mode in the discrete state (0 before, 1 after), frozen between events, so that the
/// right-hand side is smooth inside every solver step: a zero crossing g = t − time makes CVODE stop at the
/// step (to its root tolerance) and UpdateModes switches there (a time-based output would make CVODE's error
/// test fail repeatedly at the jump). Fixed-step solvers switch at the end of the integration step in which g
/// changed sign; every solver also switches at a major step (log time, sample hit) at or after `time`.
/// At the start time the mode is set from t0, so a step at t0 is seen by every block from the first output.
/// Engine caveat (engine/simulator.cc, reported): at a major step that falls exactly on `time`, a discrete
/// block with a hit there reads the value before the switch.
class Step final : public Block {
 public:
  explicit Step(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

 private:
  double time_;
  double initial_;
  double final_;
};

}  // namespace mb
