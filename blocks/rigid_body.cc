#include "blocks/rigid_body.h"

#include <limits>

#include "engine/block_roles.h"

namespace mb {

RigidBody::RigidBody(const BlockConfig& config)
    : Block(config.name),
      body_{config.parameters.Number("mass"), config.parameters.Number("damping")},
      x0_(config.parameters.Number("x0")),
      v0_(config.parameters.Number("v0")) {
  ValidateRigidBodyParameters(body_, "rigid_body '" + config.name + "'");
  DeclareInputPort("f", 1, "N", /*direct_feedthrough=*/false);
  DeclareOutputPort("x", 1, "m");
  DeclareOutputPort("v", 1, "m/s");
  DeclareContinuousState(2);
  SetSampleTime(SampleTime::Continuous());
}

void RigidBody::Initialize(const BlockContext& c) const {
  auto x = c.continuous_state();
  x(0) = x0_;
  x(1) = v0_;
}

void RigidBody::CalcOutput(const BlockContext& c) const {
  const auto x = c.continuous_state();
  c.y(0) = x(0);
  c.y(1) = x(1);
}

void RigidBody::CalcDerivatives(const BlockContext& c) const {
  const auto x = c.continuous_state();
  auto dx = c.derivatives();
  dx(0) = x(1);
  dx(1) = RigidBodyAcceleration(body_, c.u(0), x(1));
}

MB_REGISTER_BLOCK(RigidBody, BlockType{
    "rigid_body", "M·ẍ = f − B·ẋ; in f [N], outs x [m], v [m/s]; no direct feedthrough.",
    {Optional("mass", 1.0, "kg", "moving mass M > 0"),
     Bounded("damping", 0.0, "N·s/m", "viscous damping B", 0.0, std::numeric_limits<double>::infinity()),
     Optional("x0", 0.0, "m", "initial position"),
     Optional("v0", 0.0, "m/s", "initial velocity")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<RigidBody>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(RigidBody, "rigid_body", {"plant"})

}  // namespace mb
