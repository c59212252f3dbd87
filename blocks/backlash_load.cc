#include "blocks/backlash_load.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"
#include "models/physics/play_coupling.h"

namespace mb {

// The discrete state: the load's position and velocity, the motor's at the last hit, and 1 once they hold values.
struct BacklashLoadState {
  static constexpr Eigen::Index kLoadX = 0, kLoadV = 1, kMotorX = 2, kMotorV = 3, kStarted = 4, kSize = 5;
};

BacklashLoad::BacklashLoad(const BlockConfig& config)
    : Block(config.name),
      mass_(config.parameters.Number("mass")),
      omega_(2.0 * std::numbers::pi * config.parameters.Number("frequency_hz")),
      zeta_(config.parameters.Number("damping_ratio")),
      half_gap_(0.5 * config.parameters.Number("backlash")),
      load_damping_(config.parameters.Number("load_damping")),
      period_(config.sample_time ? config.sample_time->period : 0.0) {
  if (!std::isfinite(mass_)) throw std::invalid_argument(fmt::format("mass must be finite, got {}", mass_));
  if (!(omega_ > 0.0) || !std::isfinite(omega_)) {
    throw std::invalid_argument(fmt::format(
        "frequency_hz must be a finite value > 0 (the engaged shaft's mode √(k/m_L)/2π), got {}",
        config.parameters.Number("frequency_hz")));
  }
  if (!(zeta_ > 0.0) || !std::isfinite(zeta_)) {
    throw std::invalid_argument(fmt::format("damping_ratio must be a finite value > 0, got {}", zeta_));
  }
  if (!(half_gap_ >= 0.0) || !std::isfinite(half_gap_)) {
    throw std::invalid_argument(fmt::format(
        "backlash must be a finite value >= 0 (the play's full width, 0 for none), got {}", 2.0 * half_gap_));
  }
  if (!(load_damping_ >= 0.0) || !std::isfinite(load_damping_)) {
    throw std::invalid_argument(fmt::format(
        "load_damping must be a finite value >= 0 (the load's viscous friction per unit mass [1/s]), got {}",
        load_damping_));
  }
  if (!config.sample_time || !(period_ > 0.0)) {
    throw std::invalid_argument("backlash_load '" + config.name +
                                "' needs a sampleTime [Ts, offset] with Ts > 0: the load is stepped from hit to hit");
  }
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  DeclareOutputPort("f", 1, "N");
  DeclareDiscreteState(static_cast<int>(BacklashLoadState::kSize));
  SetSampleTime(*config.sample_time);
}

double BacklashLoad::Step(const BlockContext& c, double state_out[2]) const {
  const auto s = c.discrete_state();
  const double x = c.u(0), v = c.u(1);
  // The first hit: the load at the motor's position and speed, centred in the play.
  if (s(BacklashLoadState::kStarted) == 0.0) {
    state_out[0] = x;
    state_out[1] = v;
    return 0.0;
  }
  PlayLoad load{s(BacklashLoadState::kLoadX), s(BacklashLoadState::kLoadV)};
  const double acceleration = AdvancePlayLoad(s(BacklashLoadState::kMotorX), s(BacklashLoadState::kMotorV), x, v,
                                              period_, half_gap_, omega_, zeta_, load_damping_, &load);
  state_out[0] = load.x;
  state_out[1] = load.v;
  return acceleration;
}

void BacklashLoad::CalcOutput(const BlockContext& c) const {
  double load[2];
  c.y(0) = mass_ * Step(c, load);
}

void BacklashLoad::UpdateDiscrete(const BlockContext& c) const {
  double load[2];
  Step(c, load);
  auto s = c.discrete_state();
  s(BacklashLoadState::kLoadX) = load[0];
  s(BacklashLoadState::kLoadV) = load[1];
  s(BacklashLoadState::kMotorX) = c.u(0);
  s(BacklashLoadState::kMotorV) = c.u(1);
  s(BacklashLoadState::kStarted) = 1.0;
}

MB_REGISTER_BLOCK(BacklashLoad, BlockType{
    "backlash_load",
    "a load m_L behind a play of width g on a shaft of mode f (ζ), seen from the motor: f = m_L·ẍ_L, the load stepped "
    "from the motor's x and v (dead-zone two-mass model). In: x [m], v [m/s]. Discrete: needs sampleTime [Ts, offset].",
    {Required("mass", "kg", "load mass m_L behind the play"),
     Required("frequency_hz", "Hz", "the engaged shaft's mode f = √(k/m_L)/2π > 0"),
     Bounded("damping_ratio", 0.05, "", "the engaged shaft's damping ratio ζ", 0.0,
             std::numeric_limits<double>::infinity()),
     Required("backlash", "m", "the play's full width g >= 0"),
     Bounded("load_damping", 0.0, "1/s", "β = b_L/m_L, the load's own viscous friction per unit mass", 0.0,
             std::numeric_limits<double>::infinity())},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<BacklashLoad>(c); }})

// The diagnosis' suggestion made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect backlash_load: the play, mode and damping it found, the load mass its coefficient.
EffectBlockTemplate BacklashLoadEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "backlash_load";
  block.element_name = "load_behind_play";
  block.output_port = "f";
  block.inputs = {{MotionInput::kPosition, "x"}, {MotionInput::kVelocity, "v"}};
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) {
    const double frequency = BlockParameter(d, "frequency_hz");
    const double damping = BlockParameter(d, "damping_ratio");
    const double gap = BlockParameter(d, "backlash");
    if (!(frequency > 0.0) || !(damping > 0.0) || !(gap >= 0.0)) {
      throw std::invalid_argument(fmt::format(
          "{} with frequency_hz = {}, damping_ratio = {} and backlash = {}: the first two must be > 0 and the play "
          ">= 0 to suggest a block",
          d.effect, frequency, damping, gap));
    }
    return nlohmann::json{{"mass", WithUnit(BlockCoefficient(d, "load_mass"), "kg")},
                          {"frequency_hz", WithUnit(frequency, "Hz")},
                          {"damping_ratio", damping},
                          {"backlash", WithUnit(gap, "m")},
                          {"load_damping", BlockParameter(d, "load_damping")}};
  };
  block.free = {"mass", "frequency_hz", "damping_ratio", "backlash", "load_damping"};
  block.physical_range = {{"damping_ratio", {0.0, 1.0}},
                          {"mass", {0.0, std::numeric_limits<double>::infinity()}},
                          {"backlash", {0.0, std::numeric_limits<double>::infinity()}},
                          {"load_damping", {0.0, std::numeric_limits<double>::infinity()}}};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(backlash_load, BacklashLoadEffectBlock())

}  // namespace mb
