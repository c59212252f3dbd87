#include "blocks/position_periodic.h"

#include <cmath>

#include "models/diagnosis/effect_block.h"

namespace mb {

PositionPeriodic::PositionPeriodic(const BlockConfig& config)
    : Block(config.name), series_(PositionFourierSeriesOf(config.parameters)) {
  DeclareInputPort("x", 1, "m");
  DeclareOutputPort("y");
}

void PositionPeriodic::CalcOutput(const BlockContext& c) const {
  c.y(0) = series_(c.u(0));
}

MB_REGISTER_BLOCK(PositionPeriodic, BlockType{
    "position_periodic",
    "y = Σ_h a_h cos(2πh(x−x₀)/P) + b_h sin(2πh(x−x₀)/P): ripple periodic in position (cogging, screw lead). "
    "In: x [m].",
    {Bounded("period", 0.0225, "m", "spatial period P (pole pitch, screw lead)", 1e-9, 1e9),
     Bounded("harmonics", 3, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "", "a_1…a_H ([] = zeros)", ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "", "b_1…b_H ([] = zeros)", ParamType::kVector),
     Optional("position_offset", 0.0, "m", "x₀: position reference of the ripple (encoder zero of the record)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<PositionPeriodic>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect position_periodic (models/diagnosis/effects/position_periodic.cc) to a diagram.
EffectBlockTemplate PositionPeriodicEffectBlock() {
  return PositionRippleBlock("position_periodic", 3);
}

// Adds the diagnosed effect gravity (models/diagnosis/effects/gravity.cc): one harmonic of one revolution, its two
// coefficients (m·g·l·sin φ, m·g·l·cos φ) free; the period is the revolution, fixed (not refined).
EffectBlockTemplate GravityEffectBlock() {
  EffectBlockTemplate block = PositionRippleBlock("position_periodic", 1);
  block.element_name = "gravity";
  block.refinable.clear();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(position_periodic, PositionPeriodicEffectBlock())
MB_REGISTER_EFFECT_BLOCK(gravity, GravityEffectBlock())

namespace {

// Adds the grammar's friction_ripple (models/diagnosis/effects/factor_products.cc: the direction of slip × a ripple of
// the position): the ripple times tanh(v/v_s), a friction that varies along the pitch.
EffectBlockTemplate FrictionRippleEffectBlock() {
  EffectBlockTemplate block = PositionRippleBlock("position_periodic", 1);
  block.element_name = "friction_ripple";
  block.multiplier = SlipOfVelocity();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(friction_ripple, FrictionRippleEffectBlock())

namespace {

// Adds the grammar's force_constant_ripple (effects/factor_products.cc: ŷ × a ripple of the position): the ripple times
// the model's force, the force constant scaled by 1 + ripple(x) (equation-error mode).
EffectBlockTemplate ForceConstantRippleEffectBlock() {
  EffectBlockTemplate block = PositionRippleBlock("position_periodic", 1);
  block.element_name = "force_constant_ripple";
  block.multiplier = ModelForce();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(force_constant_ripple, ForceConstantRippleEffectBlock())

namespace {

// The grammar's damping_ripple (effects/factor_products.cc: v × a ripple of the position): the ripple times the
// measured velocity. (inertia_ripple, a mass along the pitch, is blocks/position_dependent_inertia.)
EffectBlockTemplate DampingRippleEffectBlock() {
  EffectBlockTemplate block = PositionRippleBlock("position_periodic", 1);
  block.element_name = "damping_ripple";
  block.multiplier = MeasuredMotion(MotionInput::kVelocity);
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(damping_ripple, DampingRippleEffectBlock())

}  // namespace mb
