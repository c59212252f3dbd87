#include "blocks/linear_motor.h"

#include <cmath>
#include <stdexcept>

#include "engine/block_roles.h"

namespace mb {

namespace {

CoggingParameters CoggingFrom(const BlockConfig& config) {
  const auto& p = config.parameters;
  CoggingParameters c;
  c.pole_pitch = p.Number("pole_pitch");
  c.amplitude = p.Number("cogging_amplitude");
  c.amplitude_velocity = p.Number("cogging_amplitude_velocity");
  c.harmonics = p.Vector("cogging_harmonics");
  c.phases = p.Vector("cogging_phases");
  if (c.phases.size() == 1 && c.harmonics.size() > 1) c.phases = Eigen::VectorXd::Constant(c.harmonics.size(), c.phases(0));
  c.offset = p.Number("cogging_offset");
  c.offset_velocity = p.Number("cogging_offset_velocity");
  c.offset_velocity_squared = p.Number("cogging_offset_velocity_squared");
  return c;
}

StribeckParameters FrictionFrom(const BlockConfig& config) {
  const auto& p = config.parameters;
  return {p.Number("coulomb_friction"), p.Number("static_friction"), p.Number("stribeck_velocity"),
          p.Number("viscous_squared"), p.Number("friction_regularization_velocity")};
}

template <class Model, class Parameters>
Model Make(const BlockConfig& config, Parameters parameters) {
  try {
    return Model(std::move(parameters));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(config.name + ": " + e.what());
  }
}

}  // namespace

LinearMotor::LinearMotor(const BlockConfig& config)
    : Block(config.name),
      mass_(config.parameters.Number("mass") + config.parameters.Number("payload_mass")),
      mass_without_payload_(config.parameters.Number("mass")),
      inverse_mass_(1.0 / mass_),
      inverse_mass_without_payload_(1.0 / mass_without_payload_),
      payload_time_(config.parameters.Number("payload_time")),
      damping_(config.parameters.Number("damping")),
      initial_position_(config.parameters.Number("initial_position")),
      initial_velocity_(config.parameters.Number("initial_velocity")),
      encoder_resolution_(config.parameters.Number("encoder_resolution")),
      cogging_(Make<CoggingForce>(config, CoggingFrom(config))),
      friction_(Make<StribeckFriction>(config, FrictionFrom(config))),
      resonance_(Make<StructuralResonance>(
          config, ResonanceParameters{config.parameters.Number("resonance_frequency_hz"),
                                      config.parameters.Number("resonance_damping_ratio"),
                                      config.parameters.Number("resonance_modal_gain")})) {
  DeclareInputPort("u", 1, "N", /*direct_feedthrough=*/false);
  DeclareOutputPort("x", 1, "m");
  DeclareOutputPort("x_true", 1, "m");
  DeclareOutputPort("velocity", 1, "m/s");
  DeclareOutputPort("disturbance", 1, "N");
  DeclareContinuousState(resonance_.enabled() ? 4 : 2);
  if (payload_time_ > 0.0) {
    DeclareDiscreteState(1);  // 1 once the payload is on
    DeclareZeroCrossings(1);  // t − payload_time
  }
  SetSampleTime(SampleTime::Continuous());
}

void LinearMotor::Initialize(const BlockContext& c) const {
  auto x = c.continuous_state();
  x(0) = initial_position_;
  x(1) = initial_velocity_;
}

void LinearMotor::CalcOutput(const BlockContext& c) const {
  const auto s = c.continuous_state();
  const double encoder = resonance_.enabled() ? s(0) + s(2) : s(0);
  c.y(0) = encoder_resolution_ > 0.0 ? encoder_resolution_ * std::floor(encoder / encoder_resolution_) : encoder;
  c.y(1) = s(0);
  c.y(2) = s(1);
  c.y(3) = Disturbance(s(0), s(1));
}

void LinearMotor::CalcDerivatives(const BlockContext& c) const {
  const auto s = c.continuous_state();
  auto ds = c.derivatives();
  const double force = c.u(0) + Disturbance(s(0), s(1));
  const bool payload_on = payload_time_ <= 0.0 || c.discrete_state()(0) > 0.5;
  const double inverse_mass = payload_on ? inverse_mass_ : inverse_mass_without_payload_;
  ds(0) = s(1);
  ds(1) = (force - damping_ * s(1)) * inverse_mass;
  if (resonance_.enabled()) {
    ds(2) = s(3);
    ds(3) = resonance_.ModalAcceleration(s(2), s(3), force * inverse_mass);
  }
}

void LinearMotor::CalcZeroCrossings(const BlockContext& c) const {
  if (payload_time_ > 0.0) c.zero_crossings()(0) = c.time() - payload_time_;
}

bool LinearMotor::UpdateModes(const BlockContext& c) const {
  if (payload_time_ <= 0.0) return false;
  auto xd = c.discrete_state();
  const double on = c.time() >= payload_time_ ? 1.0 : 0.0;
  const bool changed = xd(0) != on;
  xd(0) = on;
  return changed;
}

MB_REGISTER_BLOCK(LinearMotor, BlockType{
    "linear_motor",
    "Iron-core linear-motor twin: (M + payload)ẍ + Bẋ = u + d, d = cogging (eq. 2, harmonics of the pole pitch, "
    "velocity-dependent amplitude/offset) − Stribeck/Coulomb/velocity-dependent viscous friction; encoder "
    "quantisation; optional structural mode. In u [N]; out x (encoder) [m], x_true [m], velocity [m/s], "
    "disturbance d [N].",
    {Bounded("mass", 0.2621, "kg", "true moving mass M (the DOB's M_n = 0.2621)", 1e-9, 1e9),
     Bounded("damping", 3.0, "N*s/m", "true linear viscous damping B (the DOB's B_n = 3)", 0.0, 1e9),
     Bounded("payload_mass", 0.0, "kg", "payload m_p added to the moving mass (section 5.3)", 0.0, 1e9),
     Bounded("payload_time", 0.0, "s", "time the payload is put on (0 = from the start; > 0: picked up mid-run)", 0.0,
             1e9),
     Optional("initial_position", 0.0, "m", "x(0)"),
     Optional("initial_velocity", 0.0, "m/s", "ẋ(0)"),
     Bounded("pole_pitch", 0.0225, "m", "magnet pole pitch τ (eq. 1)", 1e-9, 1e3),
     Optional("cogging_amplitude", 0.5, "N", "α_0: cogging amplitude at rest"),
     Optional("cogging_amplitude_velocity", 0.6, "N*s/m", "α_1: amplitude growth with speed, α = α_0 + α_1|ẋ|"),
     Optional("cogging_harmonics", nlohmann::json::array({1.0, 0.25, 0.1}), "",
              "relative amplitude r_h of harmonic h = 1, 2, … of the pole pitch", ParamType::kVector),
     Optional("cogging_phases", nlohmann::json::array({0.0, 0.7, 1.9}), "rad",
              "phase φ_h of each harmonic (one value or one per harmonic)", ParamType::kVector),
     Optional("cogging_offset", 0.0, "N", "β_0: offset of eq. 2"),
     Optional("cogging_offset_velocity", 0.0, "N*s/m", "β_1: offset slope, β = β_0 + β_1 ẋ + β_2 ẋ|ẋ|"),
     Optional("cogging_offset_velocity_squared", 0.0, "N*s^2/m^2", "β_2: quadratic offset (high-speed bias)"),
     Bounded("coulomb_friction", 0.1, "N", "Coulomb level F_c", 0.0, 1e9),
     Bounded("static_friction", 0.15, "N", "Stribeck (breakaway) level F_s", 0.0, 1e9),
     Bounded("stribeck_velocity", 0.005, "m/s", "Stribeck velocity v_s", 1e-12, 1e9),
     Optional("viscous_squared", 1.5, "N*s^2/m^2",
              "velocity-dependent viscous friction b_2ẋ|ẋ| (the damping mismatch of section 2.1)"),
     Bounded("friction_regularization_velocity", 1e-3, "m/s", "v_reg of the smooth sign tanh(ẋ/v_reg)", 1e-12, 1e9),
     Bounded("encoder_resolution", 0.2e-6, "m", "encoder quantum q_e (0 = ideal sensor)", 0.0, 1.0),
     Bounded("resonance_frequency_hz", 0.0, "Hz", "structural mode frequency (used when modal gain ≠ 0)", 0.0, 1e9),
     Bounded("resonance_damping_ratio", 0.05, "", "structural mode damping ratio ζ", 0.0, 1e3),
     Optional("resonance_modal_gain", 0.0, "", "structural mode participation g (0 = rigid)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<LinearMotor>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(LinearMotor, "linear_motor", {"plant"})

}  // namespace mb
