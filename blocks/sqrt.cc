#include "blocks/sqrt.h"

#include <algorithm>
#include <cmath>

namespace mb {

Sqrt::Sqrt(const BlockConfig& config) : Block(config.name) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

void Sqrt::CalcOutput(const BlockContext& c) const { c.y(0) = std::sqrt(std::max(c.u(0), 0.0)); }

MB_REGISTER_BLOCK(Sqrt, BlockType{"sqrt", "y = √u, 0 below u = 0 (Simulink's Sqrt). Inherits its sample time.", {},
                                  SampleTimeRule::kNone, [](const BlockConfig& c) { return std::make_unique<Sqrt>(c); }})

}  // namespace mb
