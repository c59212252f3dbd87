#include "blocks/switched_gain.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

SwitchedGain::SwitchedGain(const BlockConfig& config)
    : Block(config.name), gain_(config.parameters.Number("gain")), time_(config.parameters.Number("time")) {
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("y");
  DeclareDiscreteState(1);  // mode: 0 before the switch, 1 from it on
  DeclareZeroCrossings(1);
  SetSampleTime(SampleTime::Continuous());
}

void SwitchedGain::Initialize(const BlockContext& c) const {
  c.discrete_state()(0) = c.time() - time_ >= 0.0 ? 1.0 : 0.0;
}

void SwitchedGain::CalcOutput(const BlockContext& c) const {
  c.y(0) = c.discrete_state()(0) > 0.5 ? gain_ * c.u(0) : 0.0;
}

void SwitchedGain::CalcZeroCrossings(const BlockContext& c) const { c.zero_crossings()(0) = c.time() - time_; }

bool SwitchedGain::UpdateModes(const BlockContext& c) const {
  const double mode = c.time() - time_ >= 0.0 ? 1.0 : 0.0;  // g ≥ 0: CVODE may return the root with g = 0
  const bool changed = mode != c.discrete_state()(0);
  c.discrete_state()(0) = mode;
  return changed;
}

MB_REGISTER_BLOCK(SwitchedGain, BlockType{
    "switched_gain",
    "y = 0 for t < time, gain·u for t ≥ time: a gain that switches in at a time (a payload picked up: its mass "
    "times the acceleration). In: u; out: y. The switch is a located event (zero crossing t − time).",
    {Optional("gain", 0.0, "", "the gain from the switch on"), Optional("time", 0.0, "s", "switch time")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<SwitchedGain>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect mass_change (models/diagnosis/effects/mass_change.cc): the mass picked up at the change
// time times the acceleration, its gain (the mass) free.
EffectBlockTemplate MassChangeEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "switched_gain";
  block.element_name = "payload_change";
  block.inputs = {{MotionInput::kAcceleration, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"gain", BlockCoefficient(d, "")}, {"time", WithUnit(BlockParameter(d, "change_time"), "s")}};
  };
  block.free = {"gain"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(mass_change, MassChangeEffectBlock())

}  // namespace mb
