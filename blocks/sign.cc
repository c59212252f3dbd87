#include "blocks/sign.h"

namespace mb {

Sign::Sign(const BlockConfig& config) : Block(config.name), dead_band_(config.parameters.Number("dead_band")) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

void Sign::CalcOutput(const BlockContext& c) const {
  const double u = c.u(0);
  c.y(0) = u > dead_band_ ? 1.0 : (u < -dead_band_ ? -1.0 : 0.0);
}

MB_REGISTER_BLOCK(Sign, BlockType{
    "sign", "y = sign(u): 1, 0 or −1 (Simulink's Sign), 0 within ±dead_band. Inherits its sample time.",
    {Bounded("dead_band", 0.0, "", "y = 0 for |u| ≤ dead_band (unit of u; 0 = Simulink's Sign)", 0.0, 1e300)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Sign>(c); }})

}  // namespace mb
