#include "blocks/gain.h"

#include <stdexcept>

#include "engine/block_roles.h"

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

}  // namespace mb
