#include "blocks/step.h"

namespace mb {

Step::Step(const BlockConfig& config)
    : Block(config.name),
      time_(config.parameters.Number("time")),
      initial_(config.parameters.Number("initial")),
      final_(config.parameters.Number("final")) {
  DeclareOutputPort("y");
  DeclareZeroCrossings(1);
  SetSampleTime(SampleTime::Continuous());
}

void Step::CalcOutput(const BlockContext& c) const { c.y(0) = c.time() >= time_ ? final_ : initial_; }

void Step::CalcZeroCrossings(const BlockContext& c) const { c.zero_crossings()(0) = c.time() - time_; }

MB_REGISTER_BLOCK(Step, BlockType{
    "step", "y = initial for t < time, final for t ≥ time; the solver stops at the step (zero crossing t − time).",
    {Optional("time", 1.0, "s", "step time"),
     Optional("initial", 0.0, "", "output before the step"),
     Optional("final", 1.0, "", "output from the step time on")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Step>(c); }})

}  // namespace mb
