#include "blocks/step.h"

namespace mb {

Step::Step(const BlockConfig& config)
    : Block(config.name),
      time_(config.parameters.Number("time")),
      initial_(config.parameters.Number("initial")),
      final_(config.parameters.Number("final")) {
  DeclareOutputPort("y");
  DeclareDiscreteState(1);  // mode: 0 before the step, 1 from the step on
  DeclareZeroCrossings(1);
  SetSampleTime(SampleTime::Continuous());
}

void Step::Initialize(const BlockContext& c) const { c.discrete_state()(0) = c.time() - time_ >= 0.0 ? 1.0 : 0.0; }

void Step::CalcOutput(const BlockContext& c) const { c.y(0) = c.discrete_state()(0) > 0.5 ? final_ : initial_; }

void Step::CalcZeroCrossings(const BlockContext& c) const { c.zero_crossings()(0) = c.time() - time_; }

bool Step::UpdateModes(const BlockContext& c) const {
  // g ≥ 0, not g > 0: CVODE may return the located crossing with g = 0 exactly.
  const double mode = c.time() - time_ >= 0.0 ? 1.0 : 0.0;
  const bool changed = mode != c.discrete_state()(0);
  c.discrete_state()(0) = mode;
  return changed;
}

MB_REGISTER_BLOCK(Step, BlockType{
    "step", "y = initial for t < time, final for t ≥ time; the switch is a located event (zero crossing t − time).",
    {Optional("time", 1.0, "s", "step time"),
     Optional("initial", 0.0, "", "output before the step"),
     Optional("final", 1.0, "", "output from the step time on")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Step>(c); }})

}  // namespace mb
