#include "blocks/ramped_gain.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

RampedGain::RampedGain(const BlockConfig& config)
    : Block(config.name),
      gain_(config.parameters.Number("gain")),
      start_(config.parameters.Number("start_time")),
      end_(config.parameters.Number("end_time")) {
  if (!(end_ > start_)) {
    throw std::invalid_argument(fmt::format("ramped_gain '{}': end_time {} s must lie after start_time {} s",
                                            config.name, end_, start_));
  }
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("y");
  SetSampleTime(SampleTime::Continuous());
}

void RampedGain::CalcOutput(const BlockContext& c) const {
  const double ramp = std::clamp((c.time() - start_) / (end_ - start_), 0.0, 1.0);
  c.y(0) = gain_ * ramp * c.u(0);
}

MB_REGISTER_BLOCK(RampedGain, BlockType{
    "ramped_gain",
    "y = gain·clamp((t − start_time)/(end_time − start_time), 0, 1)·u: a gain that ramps in over a time span (a "
    "parameter that drifts during a record: viscous friction as the lubricant warms). In: u; out: y.",
    {Optional("gain", 0.0, "", "the gain reached at end_time"), Optional("start_time", 0.0, "s", "the ramp starts"),
     Optional("end_time", 1.0, "s", "the ramp ends (> start_time)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<RampedGain>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect friction_drift (models/diagnosis/effects/friction_drift.cc): the change of the viscous
// friction over the record times the velocity, ramped in over the record's span, its gain (the change) free.
EffectBlockTemplate FrictionDriftEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "ramped_gain";
  block.element_name = "friction_drift";
  block.inputs = {{MotionInput::kVelocity, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"gain", BlockCoefficient(d, "")},
                          {"start_time", WithUnit(BlockParameter(d, "start_time"), "s")},
                          {"end_time", WithUnit(BlockParameter(d, "end_time"), "s")}};
  };
  block.free = {"gain"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(friction_drift, FrictionDriftEffectBlock())

}  // namespace mb
