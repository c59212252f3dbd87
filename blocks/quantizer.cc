#include "blocks/quantizer.h"

#include <cmath>
#include <stdexcept>
#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

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

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect quantization (models/diagnosis/effects/quantization.cc) to a diagram.
EffectBlockTemplate QuantizationEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "quantizer";
  block.element_name = "output_quantizer";
  block.placement = BlockPlacement::kInsertBeforeOutput;
  block.parameters = [](const DiagnosedEffect& d) {
    const double step = BlockParameter(d, "step");
    if (!(step > 0.0)) {
      throw std::invalid_argument(
          fmt::format("{} with step {}: must be > 0 to suggest a block", d.effect, step));
    }
    return nlohmann::json{{"interval", step}};
  };
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(quantization, QuantizationEffectBlock())

}  // namespace mb
