#include "blocks/constant.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

Constant::Constant(const BlockConfig& config) : Block(config.name), value_(config.parameters.Vector("value")) {
  DeclareOutputPort("y", static_cast<int>(value_.size()));
  SetSampleTime(SampleTime::Constant());
}

void Constant::CalcOutput(const BlockContext& c) const { c.output(0) = value_; }

MB_REGISTER_BLOCK(Constant, BlockType{
    "constant", "y = value (scalar or vector).",
    {Optional("value", 0.0, "", "the constant (scalar or vector)", ParamType::kVector)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Constant>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect constant_offset (models/diagnosis/effects/constant_offset.cc) to a diagram.
EffectBlockTemplate ConstantOffsetEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "constant";
  block.element_name = "offset_extra";
  block.parameters = [](const DiagnosedEffect& d) { return nlohmann::json{{"value", BlockCoefficient(d, "")}}; };
  block.free = {"value"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(constant_offset, ConstantOffsetEffectBlock())

}  // namespace mb
