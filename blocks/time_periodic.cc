#include "blocks/time_periodic.h"

#include <cmath>
#include <numbers>

#include "models/physics/fourier_series.h"
#include "models/diagnosis/effect_block.h"

namespace mb {

TimePeriodic::TimePeriodic(const BlockConfig& config)
    : Block(config.name),
      omega_(2.0 * std::numbers::pi * config.parameters.Number("frequency_hz")),
      half_chirp_(std::numbers::pi * config.parameters.Number("frequency_rate")),
      cos_(FourierCoefficients(config.parameters, "cos_coefficients")),
      sin_(FourierCoefficients(config.parameters, "sin_coefficients")) {
  DeclareOutputPort("y");
  SetSampleTime(config.sample_time ? *config.sample_time : SampleTime::Continuous());
}

void TimePeriodic::CalcOutput(const BlockContext& c) const {
  const double t = c.time();
  c.y(0) = FourierSeries(cos_, sin_, (omega_ + half_chirp_ * t) * t);
}

MB_REGISTER_BLOCK(TimePeriodic, BlockType{
    "time_periodic",
    "y = Σ_h a_h cos(hφ) + b_h sin(hφ), φ = 2π(ft + ½ḟt²): a disturbance periodic in time (external vibration), "
    "its frequency drifting at ḟ, linear in its coefficients. Continuous, or sampled with a sampleTime.",
    {Bounded("frequency_hz", 50.0, "Hz", "fundamental frequency f", 1e-9, 1e12),
     Bounded("frequency_rate", 0.0, "Hz/s", "drift ḟ of the frequency (0: fixed)", -1e12, 1e12),
     Bounded("harmonics", 1, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "", "a_1…a_H ([] = zeros)", ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "", "b_1…b_H ([] = zeros)", ParamType::kVector)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<TimePeriodic>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect time_periodic (models/diagnosis/effects/time_periodic.cc) to a diagram.
EffectBlockTemplate TimePeriodicEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "time_periodic";
  block.element_name = "vibration";
  block.parameters = [](const DiagnosedEffect& d) {
    nlohmann::json p = FourierBlockParameters(d, BlockHarmonics(d, 1));
    p["frequency_hz"] = WithUnit(BlockParameter(d, "frequency_hz"), "Hz");
    return p;
  };
  block.free = {"frequency_hz", "cos_coefficients", "sin_coefficients"};
  return block;
}

// Adds the diagnosed effect drifting_vibration (models/diagnosis/effects/drifting_vibration.cc): the same block with
// its frequency drifting.
EffectBlockTemplate DriftingVibrationEffectBlock() {
  EffectBlockTemplate block = TimePeriodicEffectBlock();
  block.element_name = "drifting_vibration";
  block.parameters = [](const DiagnosedEffect& d) {
    nlohmann::json p = FourierBlockParameters(d, BlockHarmonics(d, 1));
    p["frequency_hz"] = WithUnit(BlockParameter(d, "frequency_hz"), "Hz");
    p["frequency_rate"] = WithUnit(BlockParameter(d, "drift_rate"), "Hz/s");
    return p;
  };
  block.free = {"frequency_hz", "frequency_rate", "cos_coefficients", "sin_coefficients"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(time_periodic, TimePeriodicEffectBlock())
MB_REGISTER_EFFECT_BLOCK(drifting_vibration, DriftingVibrationEffectBlock())

}  // namespace mb
