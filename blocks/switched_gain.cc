#include "blocks/switched_gain.h"

#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

SwitchedGain::SwitchedGain(const BlockConfig& config)
    : Block(config.name),
      gain_(config.parameters.Number("gain")),
      time_(config.parameters.Number("time")),
      off_time_(config.parameters.Number("off_time")) {
  if (!(off_time_ > time_)) {
    throw std::invalid_argument(fmt::format("switched_gain '{}': off_time {} s must lie after time {} s", config.name,
                                            off_time_, time_));
  }
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("y");
  DeclareDiscreteState(1);  // mode: 1 from the switch on until the switch off, else 0
  DeclareZeroCrossings(2);
  SetSampleTime(SampleTime::Continuous());
}

void SwitchedGain::Initialize(const BlockContext& c) const {
  c.discrete_state()(0) = Mode(c.time());
}

void SwitchedGain::CalcOutput(const BlockContext& c) const {
  c.y(0) = c.discrete_state()(0) > 0.5 ? gain_ * c.u(0) : 0.0;
}

void SwitchedGain::CalcZeroCrossings(const BlockContext& c) const {
  c.zero_crossings()(0) = c.time() - time_;
  c.zero_crossings()(1) = c.time() - off_time_;
}

bool SwitchedGain::UpdateModes(const BlockContext& c) const {
  const double mode = Mode(c.time());  // g ≥ 0: CVODE may return the root with g = 0
  const bool changed = mode != c.discrete_state()(0);
  c.discrete_state()(0) = mode;
  return changed;
}

MB_REGISTER_BLOCK(SwitchedGain, BlockType{
    "switched_gain",
    "y = gain·u for time ≤ t < off_time, else 0: a gain that switches in at a time (a payload picked up: its mass "
    "times the acceleration) and out at a later one when given (the payload set down). In: u; out: y. Each switch is a "
    "located event (zero crossings t − time, t − off_time).",
    {Optional("gain", 0.0, "", "the gain while switched in"), Optional("time", 0.0, "s", "switch-on time"),
     Optional("off_time", 1e300, "s", "switch-off time (default: never)")},
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

// Adds the grammar's pair inertia_window (a × window(t): a payload carried between two times and set down): the mass
// switched in at on_time and out at off_time times the acceleration, its gain (the mass) free. The block every pair
// of a window in time is composed from (BlockFor, effect_block.h: the multiplier's factor as its input).
EffectBlockTemplate InertiaWindowEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "switched_gain";
  block.element_name = "inertia_window";
  block.inputs = {{MotionInput::kAcceleration, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"gain", BlockCoefficient(d, "")},
                          {"time", WithUnit(BlockParameter(d, "on_time"), "s")},
                          {"off_time", WithUnit(BlockParameter(d, "off_time"), "s")}};
  };
  block.free = {"gain"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(mass_change, MassChangeEffectBlock())
MB_REGISTER_EFFECT_BLOCK(inertia_window, InertiaWindowEffectBlock())

}  // namespace mb
