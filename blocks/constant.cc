#include "blocks/constant.h"

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

}  // namespace mb
