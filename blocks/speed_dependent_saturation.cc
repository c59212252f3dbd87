#include "blocks/speed_dependent_saturation.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

SpeedDependentSaturation::SpeedDependentSaturation(const BlockConfig& config)
    : Block(config.name),
      lower_(config.parameters.Number("lower")),
      upper_(config.parameters.Number("upper")),
      slope_(config.parameters.Number("speed_slope")) {
  if (lower_ > upper_) {
    throw std::invalid_argument(fmt::format("speed_dependent_saturation '{}': lower limit {} is above upper limit {}; "
                                            "swap them",
                                            config.name, lower_, upper_));
  }
  DeclareInputPort("u", 1);
  DeclareInputPort("v", 1, "m/s");
  DeclareOutputPort("y");
}

void SpeedDependentSaturation::CalcOutput(const BlockContext& c) const {
  const double shift = slope_ * c.u(1);
  c.y(0) = std::min(std::max(c.u(0), lower_ - shift), upper_ - shift);
}

MB_REGISTER_BLOCK(SpeedDependentSaturation, BlockType{
    "speed_dependent_saturation",
    "y = min(max(u, lower − speed_slope·v), upper − speed_slope·v): a saturation whose limits fall with the speed in "
    "the direction of motion (a drive running out of voltage at speed: back-EMF). In: u, v [m/s]; out: y.",
    {Optional("lower", -1.0, "", "the lower limit at standstill"),
     Optional("upper", 1.0, "", "the upper limit at standstill (>= lower)"),
     Bounded("speed_slope", 0.0, "", "k ≥ 0: the limits' fall per unit of velocity (k_t·k_e/R: N·s/m)", 0.0,
             std::numeric_limits<double>::infinity())},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<SpeedDependentSaturation>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect drive_voltage_limit (models/diagnosis/effects/drive_voltage_limit.cc): the drive's limits
// at standstill and their fall with speed on the command path (BlockPlacement::kOnCommand), reading the velocity.
EffectBlockTemplate DriveVoltageLimitEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "speed_dependent_saturation";
  block.element_name = "drive_voltage_limit";
  block.placement = BlockPlacement::kOnCommand;
  block.inputs = {{MotionInput::kVelocity, "v"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"lower", BlockParameter(d, "lower_limit")},
                          {"upper", BlockParameter(d, "upper_limit")},
                          {"speed_slope", BlockParameter(d, "speed_slope")}};
  };
  block.free = {"lower", "upper", "speed_slope"};
  block.physical_range = {{"speed_slope", {0.0, std::numeric_limits<double>::infinity()}}};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(drive_voltage_limit, DriveVoltageLimitEffectBlock())

}  // namespace mb
