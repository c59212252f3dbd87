#include "blocks/velocity_dependent_ripple.h"

#include <cmath>

#include "models/diagnosis/effect_block.h"

namespace mb {

VelocityDependentRipple::VelocityDependentRipple(const BlockConfig& config)
    : Block(config.name), series_(PositionFourierSeriesOf(config.parameters)) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  DeclareOutputPort("y");
}

void VelocityDependentRipple::CalcOutput(const BlockContext& c) const {
  c.y(0) = std::abs(c.u(1)) * series_(c.u(0));
}

MB_REGISTER_BLOCK(VelocityDependentRipple, BlockType{
    "velocity_dependent_ripple",
    "y = |v|·Σ_h a_h cos(2πh(x−x₀)/P) + b_h sin(2πh(x−x₀)/P): position-periodic ripple whose amplitude grows "
    "with speed. In: x [m], v [m/s].",
    {Bounded("period", 0.0225, "m", "spatial period P (pole pitch, screw lead)", 1e-9, 1e9),
     Bounded("harmonics", 1, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "", "a_1…a_H per unit speed ([] = zeros)",
              ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "", "b_1…b_H per unit speed ([] = zeros)",
              ParamType::kVector),
     Optional("position_offset", 0.0, "m", "x₀: position reference of the ripple (encoder zero of the record)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<VelocityDependentRipple>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect velocity_dependent_ripple (models/diagnosis/effects/velocity_dependent_ripple.cc) to a diagram.
EffectBlockTemplate VelocityDependentRippleEffectBlock() {
  return PositionRippleBlock("velocity_dependent_ripple", 1, {{MotionInput::kVelocity, "v"}});
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(velocity_dependent_ripple, VelocityDependentRippleEffectBlock())

}  // namespace mb
