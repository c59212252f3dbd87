#include "blocks/bump.h"

#include <cmath>
#include <numbers>

#include "models/diagnosis/effect_block.h"

namespace mb {

Bump::Bump(const BlockConfig& config)
    : Block(config.name),
      center_(config.parameters.Number("center")),
      half_width_(config.parameters.Number("half_width")),
      flat_(config.parameters.Number("flat")),
      gain_(config.parameters.Number("gain")) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

double Bump::Shape(double z, double flat) noexcept {
  const double a = std::abs(z);
  if (a <= flat) return 1.0;
  if (a >= 1.0) return 0.0;
  const double c = std::cos(0.5 * std::numbers::pi * (a - flat) / (1.0 - flat));
  return c * c;
}

void Bump::CalcOutput(const BlockContext& c) const {
  c.y(0) = gain_ * Shape((c.u(0) - center_) / half_width_, flat_);
}

namespace {
// A parameter without a default that must be positive (its bound checked on load and kept by the refit).
ParamSpec RequiredPositive(const char* name, const char* description) {
  ParamSpec spec = Required(name, "", description);
  spec.min = 1e-12;
  return spec;
}
}  // namespace

MB_REGISTER_BLOCK(Bump, BlockType{
    "bump",
    "y = gain · b((u − c)/w): over one stretch [c − w, c + w] of u, a flat top of f·w with cos² flanks (a Tukey window; "
    "f = 0 a cos² bump, f → 1 a box). Inherits its sample time.",
    {Required("center", "", "c: the middle of the stretch (unit of u)"),
     RequiredPositive("half_width", "w > 0: it acts over [c − w, c + w] (unit of u)"),
     Bounded("flat", 0.0, "", "f: the flat top's share of w, 0 ≤ f ≤ 0.99", 0.0, 0.99),
     Optional("gain", 1.0, "", "the value on the flat top (unit of y)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Bump>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// A local effect (factor_tables.cc, position_local: cos²(π(x − c)/(2w)) over [c − w, c + w]) as a bump of the
// position: the diagnosed centre and half-width, no flat top, the joint fit's coefficient as its gain; the gain free
// and the stretch's place, width and flat top refinable, so that the refit shapes the stretch with four parameters. A
// table of 37 entries free in their place fitted the training record's noise where the motion crossed the stretch
// rarely (grammar seed 22: 0.131 N on the training record, 0.224 N held out against a floor of 0.137 N), and with its
// size alone refit a stretch that is no cos² stayed 1.4 × above the floor (seeds 43, 225).
EffectBlockTemplate LocalBumpBlock(const char* element_name) {
  EffectBlockTemplate block;
  block.block_type = "bump";
  block.element_name = element_name;
  block.inputs = {{MotionInput::kPosition, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"center", BlockParameter(d, "center")},
                          {"half_width", BlockParameter(d, "half_width")},
                          {"flat", 0.0},
                          {"gain", BlockCoefficient(d, "")}};
  };
  block.free = {"gain"};
  block.refinable = {"center", "half_width", "flat"};
  return block;
}

// local_friction: the bump times the direction of slip tanh(v/v_s) (a friction at one place). A force of one place
// alone is not proposed by the catalogue: at the ends of the travel a bump is confounded with the reversals, and
// inside it position_dependent_force's smooth basis covers it.
EffectBlockTemplate LocalFrictionEffectBlock() {
  EffectBlockTemplate block = LocalBumpBlock("local_friction");
  block.multiplier = SlipOfVelocity();
  return block;
}

// local_damping: the bump times the measured velocity (viscous drag at one place).
EffectBlockTemplate LocalDampingEffectBlock() {
  EffectBlockTemplate block = LocalBumpBlock("local_damping");
  block.multiplier = MeasuredMotion(MotionInput::kVelocity);
  return block;
}

// local_force_constant: the bump times the model's force (a force constant that changes over one stretch: a chipped
// or demagnetised magnet).
EffectBlockTemplate LocalForceConstantEffectBlock() {
  EffectBlockTemplate block = LocalBumpBlock("local_force_constant");
  block.multiplier = ModelForce();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(local_friction, LocalFrictionEffectBlock())
// The grammar's local_force (one × position_local): the bump alone, a force at one place. It is also the block every
// other multiplier × position_local pair without its own is made from (BlockFor, models/diagnosis/effect_block.h).
MB_REGISTER_EFFECT_BLOCK(local_force, LocalBumpBlock("local_force"))
MB_REGISTER_EFFECT_BLOCK(local_damping, LocalDampingEffectBlock())
MB_REGISTER_EFFECT_BLOCK(local_force_constant, LocalForceConstantEffectBlock())

}  // namespace mb
