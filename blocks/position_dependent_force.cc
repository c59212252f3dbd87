#include "blocks/position_dependent_force.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

PositionDependentForce::PositionDependentForce(const BlockConfig& config)
    : Block(config.name),
      center_(config.parameters.Number("center")),
      half_range_(config.parameters.Number("half_range")),
      coefficients_(config.parameters.Vector("coefficients")) {
  DeclareInputPort("x", 1, "m");
  DeclareOutputPort("f", 1, "N");
}

void PositionDependentForce::CalcOutput(const BlockContext& c) const {
  const double xi = (c.u(0) - center_) / half_range_;
  double power = 1.0, f = 0.0;
  for (Eigen::Index j = 0; j < coefficients_.size(); ++j) {
    power *= xi;
    f += coefficients_(j) * power;
  }
  c.y(0) = f;
}

MB_REGISTER_BLOCK(PositionDependentForce, BlockType{
    "position_dependent_force",
    "f = Σ_j c_j·((x − x₀)/h)^j: a smooth force of position (spring, cable carrier, magnet, hardening "
    "suspension). In: x [m].",
    {Optional("center", 0.0, "m", "x₀: the middle of the travel"),
     Bounded("half_range", 0.1, "m", "h: half the travel (normalises the polynomial)", 1e-12, 1e9),
     Optional("coefficients", nlohmann::json::array(), "N", "c_1…c_J, the force at ξ = 1 per power",
              ParamType::kVector)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<PositionDependentForce>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect position_dependent_force (models/diagnosis/effects/position_dependent_force.cc) to a diagram.
EffectBlockTemplate PositionDependentForceEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "position_dependent_force";
  block.element_name = "position_force";
  block.output_port = "f";
  block.inputs = {{MotionInput::kPosition, "x"}};
  block.parameters = [](const DiagnosedEffect& d) {
    nlohmann::json coefficients = nlohmann::json::array();
    for (Eigen::Index j = 0; j < d.coefficients.size(); ++j) coefficients.push_back(d.coefficients(j));
    return nlohmann::json{{"center", WithUnit(BlockParameter(d, "center"), "m")},
                          {"half_range", WithUnit(BlockParameter(d, "half_range"), "m")},
                          {"coefficients", coefficients}};
  };
  block.free = {"coefficients"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(position_dependent_force, PositionDependentForceEffectBlock())

namespace {

// Adds the grammar's friction_along_travel (models/diagnosis/effects/factor_products.cc: the direction of slip × a
// cubic of the position over the travel): the cubic times tanh(v/v_s), a friction that changes along the rail.
EffectBlockTemplate FrictionAlongTravelEffectBlock() {
  EffectBlockTemplate block = PositionDependentForceEffectBlock();
  block.element_name = "friction_along_travel";
  block.multiplier = SlipOfVelocity();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(friction_along_travel, FrictionAlongTravelEffectBlock())

namespace {

// Adds the grammar's force_constant_along_travel (ŷ × a cubic of the position over the travel): the cubic times the
// model's force, a force constant that changes along the rail (the air gap varying).
EffectBlockTemplate ForceConstantAlongTravelEffectBlock() {
  EffectBlockTemplate block = PositionDependentForceEffectBlock();
  block.element_name = "force_constant_along_travel";
  block.multiplier = ModelForce();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(force_constant_along_travel, ForceConstantAlongTravelEffectBlock())

}  // namespace mb
