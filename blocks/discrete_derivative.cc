#include "blocks/discrete_derivative.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

// Discrete state: [u[k−1], 1 once an input has been sampled].
DiscreteDerivative::DiscreteDerivative(const BlockConfig& config)
    : Block(config.name), gain_(config.parameters.Number("gain")), period_(config.sample_time->period) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
  DeclareDiscreteState(2);
  SetSampleTime(*config.sample_time);
}

void DiscreteDerivative::Initialize(const BlockContext& c) const { c.discrete_state().setZero(); }

void DiscreteDerivative::CalcOutput(const BlockContext& c) const {
  const auto x = c.discrete_state();
  c.y(0) = x(1) > 0.0 ? gain_ * (c.u(0) - x(0)) / period_ : 0.0;
}

void DiscreteDerivative::UpdateDiscrete(const BlockContext& c) const {
  auto x = c.discrete_state();
  x(0) = c.u(0);
  x(1) = 1.0;
}

MB_REGISTER_BLOCK(DiscreteDerivative, BlockType{
    "discrete_derivative",
    "y[k] = gain·(u[k] − u[k−1])/Ts (Simulink's Discrete Derivative); the first output is 0 (u[−1] = u[0]). "
    "Discrete: needs sampleTime [Ts, offset].",
    {Optional("gain", 1.0, "", "K: the output per unit rate of the input (unit of y per unit of u per second)")},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<DiscreteDerivative>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the grammar's logged_column_rate (models/diagnosis/effects/logged_column.cc: the residual follows the rate of a
// log column the diagram did not read): a discrete derivative of an input connector reading the column, its gain the
// joint fit's coefficient (free), summed into the force; sampled at the diagram's step.
EffectBlockTemplate LoggedColumnRateEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "discrete_derivative";
  block.element_name = "coupling_rate";
  block.log_column_port = "u";
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) { return nlohmann::json{{"gain", BlockCoefficient(d, "")}}; };
  block.free = {"gain"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(logged_column_rate, LoggedColumnRateEffectBlock())

}  // namespace mb
