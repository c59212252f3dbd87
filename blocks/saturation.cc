#include "blocks/saturation.h"

#include <stdexcept>

#include "models/diagnosis/effect_block.h"

namespace mb {

Saturation::Saturation(const BlockConfig& config)
    : Block(config.name), lower_(config.parameters.Number("lower")), upper_(config.parameters.Number("upper")) {
  if (lower_ > upper_) {
    throw std::invalid_argument("lower limit " + std::to_string(lower_) + " is above upper limit " +
                                std::to_string(upper_) + "; swap them");
  }
  const int width = config.parameters.Integer("width");
  DeclareInputPort("u", width);
  DeclareOutputPort("y", width);
}

void Saturation::CalcOutput(const BlockContext& c) const {
  c.output(0) = c.input(0).cwiseMax(lower_).cwiseMin(upper_);
}

MB_REGISTER_BLOCK(Saturation, BlockType{
    "saturation", "y = min(max(u, lower), upper), element-wise. Inherits its sample time.",
    {Optional("lower", -1.0, "", "lower limit"),
     Optional("upper", 1.0, "", "upper limit (>= lower)"),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Saturation>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect drive_saturation (models/diagnosis/effects/drive_saturation.cc): the drive's limits on
// the command path (BlockPlacement::kOnCommand), in the command's unit.
EffectBlockTemplate DriveSaturationEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "saturation";
  block.element_name = "drive_limit";
  block.placement = BlockPlacement::kOnCommand;
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"lower", BlockParameter(d, "lower_limit")}, {"upper", BlockParameter(d, "upper_limit")}};
  };
  block.free = {"lower", "upper"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(drive_saturation, DriveSaturationEffectBlock())

}  // namespace mb
