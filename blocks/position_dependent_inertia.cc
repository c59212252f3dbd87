#include "blocks/position_dependent_inertia.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

PositionDependentInertia::PositionDependentInertia(const BlockConfig& config)
    : Block(config.name),
      mass_(PositionFourierSeriesOf(config.parameters)),
      acceleration_input_(config.parameters.Bool("acceleration_input")) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  if (acceleration_input_) DeclareInputPort("a", 1, "m/s^2");
  DeclareOutputPort("y", 1, "N");
  DeclareOutputPort("mass", 1, "kg");
}

void PositionDependentInertia::CalcOutput(const BlockContext& c) const {
  const double x = c.u(0), v = c.u(1), a = acceleration_input_ ? c.u(2) : 0.0;
  const double m = mass_(x);
  c.y(0) = m * a + 0.5 * mass_.Slope(x) * v * v;
  c.y(1) = m;
}

MB_REGISTER_BLOCK(PositionDependentInertia, BlockType{
    "position_dependent_inertia",
    "y = M(x)·a + ½M′(x)·v², M(x) = Σ_h a_h cos(2πh(x−x₀)/P) + b_h sin(2πh(x−x₀)/P): the force of a moving mass "
    "that varies with position (an arm, a linkage, a cam; Lagrange's equation). In: x [m], v [m/s], a [m/s²] (not "
    "with acceleration_input false: y = ½M′(x)·v², M(x)·a left to a plant whose mass input reads \"mass\"). Out: y "
    "[N], mass M(x) [kg].",
    {Bounded("period", 0.0225, "m", "spatial period P of the mass's variation", 1e-9, 1e9),
     Bounded("harmonics", 1, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "kg", "a_1…a_H ([] = zeros)", ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "kg", "b_1…b_H ([] = zeros)", ParamType::kVector),
     Optional("position_offset", 0.0, "m", "x₀: position reference of the variation (encoder zero of the record)"),
     Optional("acceleration_input", true, "", "false: no input a, y = ½M′(x)·v² (the plant takes M(x) as its mass)",
              ParamType::kBool)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<PositionDependentInertia>(c); }})

// The diagnosis' suggestion made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the grammar's inertia_ripple (models/diagnosis/effects/factor_products.cc: a mass periodic in the position) to a
// diagram: the block on the measured position, velocity and acceleration.
EffectBlockTemplate InertiaRippleEffectBlock() {
  EffectBlockTemplate block = PositionRippleBlock(
      "position_dependent_inertia", 1, {{MotionInput::kVelocity, "v"}, {MotionInput::kAcceleration, "a"}});
  block.element_name = "inertia_ripple";
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(inertia_ripple, InertiaRippleEffectBlock())

}  // namespace mb
