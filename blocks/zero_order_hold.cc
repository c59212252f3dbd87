#include "blocks/zero_order_hold.h"

namespace mb {

ZeroOrderHold::ZeroOrderHold(const BlockConfig& config) : Block(config.name) {
  const int width = config.parameters.Integer("width");
  DeclareInputPort("u", width);
  DeclareOutputPort("y", width);
  SetSampleTime(*config.sample_time);
}

void ZeroOrderHold::CalcOutput(const BlockContext& c) const { c.output(0) = c.input(0); }

MB_REGISTER_BLOCK(ZeroOrderHold, BlockType{
    "zero_order_hold", "y = u(t_k), held until the next hit. Discrete: needs sampleTime [Ts, offset].",
    {Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<ZeroOrderHold>(c); }})

}  // namespace mb
