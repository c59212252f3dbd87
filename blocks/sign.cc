#include "blocks/sign.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {

Sign::Sign(const BlockConfig& config)
    : Block(config.name),
      dead_band_(config.parameters.Number("dead_band")),
      regularization_velocity_(config.parameters.Number("regularization_velocity")) {
  if (dead_band_ > 0.0 && regularization_velocity_ > 0.0) {
    throw std::invalid_argument(fmt::format(
        "element '{}' (sign): give a dead_band or a regularization_velocity, not both (got {} and {})", config.name,
        dead_band_, regularization_velocity_));
  }
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

void Sign::CalcOutput(const BlockContext& c) const {
  const double u = c.u(0);
  if (regularization_velocity_ > 0.0) {
    c.y(0) = std::tanh(u / regularization_velocity_);
    return;
  }
  c.y(0) = u > dead_band_ ? 1.0 : (u < -dead_band_ ? -1.0 : 0.0);
}

MB_REGISTER_BLOCK(Sign, BlockType{
    "sign", "y = sign(u): 1, 0 or −1 (Simulink's Sign), 0 within ±dead_band; or tanh(u/regularization_velocity), "
    "smooth through 0. Inherits its sample time.",
    {Bounded("dead_band", 0.0, "", "y = 0 for |u| ≤ dead_band (unit of u; 0 = Simulink's Sign)", 0.0, 1e300),
     Bounded("regularization_velocity", 0.0, "",
             "u_r > 0: y = tanh(u/u_r), the regularised sign (unit of u; 0 = none; not with a dead_band)", 0.0, 1e300)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Sign>(c); }})

}  // namespace mb
