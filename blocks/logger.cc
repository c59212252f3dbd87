#include "blocks/logger.h"

namespace mb {

Logger::Logger(const BlockConfig& config) : Block(config.name) {
  const int width = config.parameters.Integer("width");
  DeclareInputPort("u", width);
  DeclareOutputPort("y", width);
}

void Logger::CalcOutput(const BlockContext& c) const { c.output(0) = c.input(0); }

MB_REGISTER_BLOCK(Logger, BlockType{
    "logger", "y = u: a named sink; list \"<name>.y\" in the diagram's \"log\" to record its input.",
    {Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Logger>(c); }})

}  // namespace mb
