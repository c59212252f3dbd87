#include "blocks/ramped_gain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

RampedGain::RampedGain(const BlockConfig& config)
    : Block(config.name),
      gain_(config.parameters.Number("gain")),
      start_(config.parameters.Number("start_time")),
      end_(config.parameters.Number("end_time")),
      time_constant_(config.parameters.Number("time_constant")),
      exponential_(config.parameters.String("shape") == "exponential") {
  if (exponential_ && !(time_constant_ > 0.0)) {
    throw std::invalid_argument(fmt::format("ramped_gain '{}': shape \"exponential\" needs time_constant > 0 s, got "
                                            "{} s",
                                            config.name, time_constant_));
  }
  if (!exponential_ && !(end_ > start_)) {
    throw std::invalid_argument(fmt::format("ramped_gain '{}': end_time {} s must lie after start_time {} s",
                                            config.name, end_, start_));
  }
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("y");
  SetSampleTime(SampleTime::Continuous());
}

void RampedGain::CalcOutput(const BlockContext& c) const {
  const double ramp = exponential_ ? (c.time() < start_ ? 0.0 : -std::expm1(-(c.time() - start_) / time_constant_))
                                   : std::clamp((c.time() - start_) / (end_ - start_), 0.0, 1.0);
  c.y(0) = gain_ * ramp * c.u(0);
}

MB_REGISTER_BLOCK(RampedGain, BlockType{
    "ramped_gain",
    "y = gain·ρ(t)·u, ρ = clamp((t − start_time)/(end_time − start_time), 0, 1) (shape \"linear\") or "
    "1 − exp(−(t − start_time)/time_constant) from start_time on (shape \"exponential\"): a gain that ramps in over a "
    "time span or settles as a first-order warm-up (a parameter that drifts during a record: viscous friction as the "
    "lubricant warms). In: u; out: y.",
    {Optional("gain", 0.0, "", "the gain reached at end_time (linear) or once settled (exponential)"),
     Optional("start_time", 0.0, "s", "the ramp or the warm-up starts"),
     Optional("end_time", 1.0, "s", "the linear ramp ends (> start_time)"),
     Choice("shape", "linear", "\"linear\" (a ramp to end_time) or \"exponential\" (1 − exp(−(t − start_time)/"
            "time_constant))", {"linear", "exponential"}),
     Bounded("time_constant", 1.0, "s", "T of shape \"exponential\" (> 0): 63 % of the gain at start_time + T", 0.0,
             std::numeric_limits<double>::infinity())},
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

// Adds the diagnosed effect friction_warm_up (models/diagnosis/effects/friction_warm_up.cc): the change of the viscous
// friction once warm times the velocity, settling from the record's start with the diagnosed time constant, its gain
// (the change) free.
EffectBlockTemplate FrictionWarmUpEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "ramped_gain";
  block.element_name = "friction_warm_up";
  block.inputs = {{MotionInput::kVelocity, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    const double time_constant = BlockParameter(d, "time_constant");
    if (!(time_constant > 0.0)) {
      throw std::invalid_argument(fmt::format("effect '{}': time_constant {} s must be > 0", d.effect, time_constant));
    }
    return nlohmann::json{{"gain", BlockCoefficient(d, "")},
                          {"shape", "exponential"},
                          {"start_time", WithUnit(BlockParameter(d, "start_time"), "s")},
                          {"time_constant", WithUnit(time_constant, "s")}};
  };
  block.free = {"gain"};
  // The diagnosis found T with its first-order regressor; the diagram's own shape (a force constant's share of the
  // drive's force, ŷ·r/(1 − r)) may settle it elsewhere, and T enters smoothly: refit with the gain.
  block.refinable = {"time_constant"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(friction_drift, FrictionDriftEffectBlock())
MB_REGISTER_EFFECT_BLOCK(friction_warm_up, FrictionWarmUpEffectBlock())

}  // namespace mb
