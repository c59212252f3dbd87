#include "blocks/unit_delay.h"

namespace mb {

UnitDelay::UnitDelay(const BlockConfig& config)
    : Block(config.name), initial_condition_(config.parameters.Number("initial_condition")) {
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/false);
  DeclareOutputPort("y");
  DeclareDiscreteState(1);
  SetSampleTime(*config.sample_time);
}

void UnitDelay::Initialize(const BlockContext& c) const { c.discrete_state()(0) = initial_condition_; }
void UnitDelay::CalcOutput(const BlockContext& c) const { c.y(0) = c.discrete_state()(0); }
void UnitDelay::UpdateDiscrete(const BlockContext& c) const { c.discrete_state()(0) = c.u(0); }

MB_REGISTER_BLOCK(UnitDelay, BlockType{
    "unit_delay", "y[k] = u[k−1] (z⁻¹), y[0] = initial_condition. Discrete: needs sampleTime [Ts, offset].",
    {Optional("initial_condition", 0.0, "", "output before the first update")},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<UnitDelay>(c); }})

}  // namespace mb
