#include "blocks/rigid_body.h"

#include <algorithm>
#include <limits>

#include "engine/block_roles.h"

namespace mb {

RigidBody::RigidBody(const BlockConfig& config)
    : Block(config.name),
      body_{config.parameters.Number("mass"), config.parameters.Number("damping")},
      mass_input_(config.parameters.Bool("mass_input")),
      x0_(config.parameters.Number("x0")),
      v0_(config.parameters.Number("v0")) {
  ValidateRigidBodyParameters(body_, "rigid_body '" + config.name + "'");
  DeclareInputPort("f", 1, "N", /*direct_feedthrough=*/false);
  if (mass_input_) DeclareInputPort("added_mass", 1, "kg", /*direct_feedthrough=*/false);
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
  if (!mass_input_) {
    dx(1) = RigidBodyAcceleration(body_, c.u(0), x(1));
    return;
  }
  constexpr double kLeastMassShare = 1e-3;  // of M: the total the added mass may leave
  RigidBodyParameters scheduled = body_;
  scheduled.mass = std::max(body_.mass + c.u(1), kLeastMassShare * body_.mass);
  dx(1) = RigidBodyAcceleration(scheduled, c.u(0), x(1));
}

MB_REGISTER_BLOCK(RigidBody, BlockType{
    "rigid_body",
    "M·ẍ = f − B·ẋ; in f [N] (and, with mass_input, added_mass ΔM [kg]: (M + ΔM)·ẍ), outs x [m], v [m/s]; no direct "
    "feedthrough.",
    {Optional("mass", 1.0, "kg", "moving mass M > 0"),
     Bounded("damping", 0.0, "N·s/m", "viscous damping B", 0.0, std::numeric_limits<double>::infinity()),
     Optional("x0", 0.0, "m", "initial position"),
     Optional("v0", 0.0, "m/s", "initial velocity"),
     Optional("mass_input", false, "", "a second input \"added_mass\" [kg] adds to the mass (a scheduled mass)",
              ParamType::kBool)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<RigidBody>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(RigidBody, "rigid_body", {"plant"})

}  // namespace mb
