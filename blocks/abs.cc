#include "blocks/abs.h"

#include <cmath>

namespace mb {

Abs::Abs(const BlockConfig& config) : Block(config.name) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

void Abs::CalcOutput(const BlockContext& c) const { c.y(0) = std::abs(c.u(0)); }

MB_REGISTER_BLOCK(Abs, BlockType{"abs", "y = |u| (Simulink's Abs). Inherits its sample time.", {},
                                 SampleTimeRule::kNone, [](const BlockConfig& c) { return std::make_unique<Abs>(c); }})

}  // namespace mb
