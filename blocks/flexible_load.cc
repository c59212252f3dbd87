#include "blocks/flexible_load.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

FlexibleLoad::FlexibleLoad(const BlockConfig& config)
    : Block(config.name),
      mass_(config.parameters.Number("mass")),
      omega_(2.0 * std::numbers::pi * config.parameters.Number("frequency_hz")),
      zeta_(config.parameters.Number("damping_ratio")) {
  if (!std::isfinite(mass_)) throw std::invalid_argument(fmt::format("mass must be finite, got {}", mass_));
  if (!(omega_ > 0.0) || !std::isfinite(omega_)) {
    throw std::invalid_argument(fmt::format(
        "frequency_hz must be a finite value > 0 (the mode's natural frequency √(k/m)/2π), got {}",
        config.parameters.Number("frequency_hz")));
  }
  if (!(zeta_ > 0.0) || !std::isfinite(zeta_)) {
    throw std::invalid_argument(fmt::format(
        "damping_ratio must be a finite value > 0 (typically 0.005–0.1 for a structural mode), got {}", zeta_));
  }
  DeclareInputPort("a", 1, "m/s^2", /*direct_feedthrough=*/false);
  DeclareOutputPort("f", 1, "N");
  DeclareContinuousState(2);  // e = x_load − x_motor [m], ė [m/s]
  SetSampleTime(SampleTime::Continuous());
}

void FlexibleLoad::CalcOutput(const BlockContext& c) const {
  const auto x = c.continuous_state();
  c.y(0) = -mass_ * (omega_ * omega_ * x(0) + 2.0 * zeta_ * omega_ * x(1));
}

void FlexibleLoad::CalcDerivatives(const BlockContext& c) const {
  const auto x = c.continuous_state();
  auto dx = c.derivatives();
  dx(0) = x(1);
  dx(1) = -omega_ * omega_ * x(0) - 2.0 * zeta_ * omega_ * x(1) - c.u(0);
}

MB_REGISTER_BLOCK(FlexibleLoad, BlockType{
    "flexible_load",
    "two-mass model seen from the motor: a load m on a spring–damper (mode f_r, ζ); in a [m/s²], out "
    "f = m(2ζω_r s + ω_r²)/(s² + 2ζω_r s + ω_r²)·a [N]. Continuous; no direct feedthrough.",
    {Required("mass", "kg", "load mass m behind the compliance"),
     Required("frequency_hz", "Hz", "natural frequency f_r = √(k/m)/2π > 0"),
     Bounded("damping_ratio", 0.02, "", "damping ratio ζ = c/(2√(km))", 0.0, std::numeric_limits<double>::infinity())},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<FlexibleLoad>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect resonance (models/diagnosis/effects/resonance.cc) to a diagram.
EffectBlockTemplate ResonanceEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "flexible_load";
  block.element_name = "flexible_load";
  block.output_port = "f";
  block.inputs = {{MotionInput::kAcceleration, "a"}};
  block.parameters = [](const DiagnosedEffect& d) {
    const double frequency = BlockParameter(d, "frequency_hz");
    const double damping = BlockParameter(d, "damping_ratio");
    if (!(frequency > 0.0) || !(damping > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "{} with frequency_hz = {} and damping_ratio = {}: both must be > 0 to suggest a block", d.effect,
          frequency, damping));
    }
    return nlohmann::json{{"mass", WithUnit(BlockCoefficient(d, "response"), "kg")},
                          {"frequency_hz", WithUnit(frequency, "Hz")},
                          {"damping_ratio", damping}};
  };
  block.free = {"mass", "frequency_hz", "damping_ratio"};
  // An overdamped "mode" (ζ ≥ 1) has no resonance: the refit turned it into a broad low-pass of the acceleration.
  block.physical_range = {{"damping_ratio", {0.0, 1.0}}, {"mass", {0.0, std::numeric_limits<double>::infinity()}}};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(resonance, ResonanceEffectBlock())

}  // namespace mb
