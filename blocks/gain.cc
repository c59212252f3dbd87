#include "blocks/gain.h"

#include <limits>
#include <stdexcept>
#include <utility>

#include "engine/block_roles.h"
#include "models/diagnosis/effect_block.h"

namespace mb {

Gain::Gain(const BlockConfig& config) : Block(config.name), gain_(config.parameters.Vector("gain")) {
  const int width = config.parameters.Integer("width");
  if (gain_.size() != 1 && gain_.size() != width) {
    throw std::invalid_argument("gain has " + std::to_string(gain_.size()) + " entries; give one or `width` entries");
  }
  if (gain_.size() == 1) gain_ = Eigen::VectorXd::Constant(width, gain_(0));
  DeclareInputPort("u", width);
  DeclareOutputPort("y", width);
}

void Gain::CalcOutput(const BlockContext& c) const { c.output(0) = gain_.cwiseProduct(c.input(0)); }

MB_REGISTER_BLOCK(Gain, BlockType{
    "gain", "y = K·u, element-wise. Inherits its sample time.",
    {Optional("gain", 1.0, "", "gain K (scalar, or one entry per element)", ParamType::kVector),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Gain>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(Gain, "gain", {"pd_proportional_gain", "pd_derivative_gain"})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// A gain element on a motion input (port "u") summed into the output, its gain the effect's coefficient, free.
EffectBlockTemplate GainEffectBlock(const std::string& element_name, MotionInput input) {
  EffectBlockTemplate block;
  block.block_type = "gain";
  block.element_name = element_name;
  block.inputs = {{input, "u"}};
  block.parameters = [](const DiagnosedEffect& d) { return nlohmann::json{{"gain", BlockCoefficient(d, "")}}; };
  block.free = {"gain"};
  return block;
}

// Adds the diagnosed effect viscous_friction (models/diagnosis/effects/viscous_friction.cc) to a diagram.
EffectBlockTemplate ViscousFrictionEffectBlock() {
  return GainEffectBlock("viscous_extra", MotionInput::kVelocity);
}

// Adds the diagnosed effect mass_mismatch (models/diagnosis/effects/mass_mismatch.cc) to a diagram.
EffectBlockTemplate MassMismatchEffectBlock() {
  return GainEffectBlock("payload", MotionInput::kAcceleration);
}

// Adds the diagnosed effect quadratic_drag (models/diagnosis/effects/quadratic_drag.cc): the gain on the velocity times
// its abs, c·v·|v|.
EffectBlockTemplate QuadraticDragEffectBlock() {
  EffectBlockTemplate block = GainEffectBlock("quadratic_drag", MotionInput::kVelocity);
  block.multiplier = MotionMultiplier{"abs", MotionInput::kVelocity, [](const DiagnosedEffect&) {
                                        return nlohmann::json::object();
                                      },
                                      {}};
  block.physical_range = {{"gain", {0.0, std::numeric_limits<double>::infinity()}}};  // a drag dissipates: c ≥ 0
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(viscous_friction, ViscousFrictionEffectBlock())
MB_REGISTER_EFFECT_BLOCK(mass_mismatch, MassMismatchEffectBlock())
MB_REGISTER_EFFECT_BLOCK(quadratic_drag, QuadraticDragEffectBlock())

namespace {

// Adds the grammar's logged_column (models/diagnosis/effects/logged_column.cc: the residual follows a log column the
// diagram did not read) to a diagram: a gain on an input connector reading the column, summed into the force.
EffectBlockTemplate ColumnGainEffectBlock(const char* element_name) {
  EffectBlockTemplate block;
  block.block_type = "gain";
  block.element_name = element_name;
  block.log_column_port = "u";
  block.parameters = [](const DiagnosedEffect& d) { return nlohmann::json{{"gain", BlockCoefficient(d, "")}}; };
  block.free = {"gain"};
  return block;
}

// The grammar's column_damping (effects/factor_products.cc: v × an unread column): the gain on the column times the
// velocity.
EffectBlockTemplate ColumnProductEffectBlock(const char* element_name, MotionMultiplier multiplier) {
  EffectBlockTemplate block = ColumnGainEffectBlock(element_name);
  block.multiplier = std::move(multiplier);
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(logged_column, ColumnGainEffectBlock("coupling"))
MB_REGISTER_EFFECT_BLOCK(column_damping,
                         ColumnProductEffectBlock("column_damping", MeasuredMotion(MotionInput::kVelocity)))
MB_REGISTER_EFFECT_BLOCK(column_force_constant, ColumnProductEffectBlock("column_force_constant", ModelForce()))

}  // namespace mb
