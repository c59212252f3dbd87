#include "blocks/quantizer.h"

#include <cmath>
#include <stdexcept>

namespace mb {

Quantizer::Quantizer(const BlockConfig& config) : Block(config.name), interval_(config.parameters.Number("interval")) {
  if (!(interval_ > 0.0)) {
    throw std::invalid_argument("interval must be > 0 (the quantization step q), got " + std::to_string(interval_));
  }
  const int width = config.parameters.Integer("width");
  DeclareInputPort("u", width);
  DeclareOutputPort("y", width);
}

void Quantizer::CalcOutput(const BlockContext& c) const {
  const auto u = c.input(0);
  auto y = c.output(0);
  for (Eigen::Index i = 0; i < u.size(); ++i) y(i) = interval_ * std::round(u(i) / interval_);
}

MB_REGISTER_BLOCK(Quantizer, BlockType{
    "quantizer", "y = q·round(u/q), element-wise (encoder, DAC). Inherits its sample time.",
    {Optional("interval", 1.0, "", "quantization interval q > 0 (unit of u)"),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Quantizer>(c); }})

}  // namespace mb
