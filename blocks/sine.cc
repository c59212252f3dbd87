#include "blocks/sine.h"

#include <cmath>
#include <numbers>

namespace mb {

Sine::Sine(const BlockConfig& config)
    : Block(config.name),
      amplitude_(config.parameters.Number("amplitude")),
      omega_(2.0 * std::numbers::pi * config.parameters.Number("frequency_hz")),
      phase_(config.parameters.Number("phase")),
      bias_(config.parameters.Number("bias")) {
  DeclareOutputPort("y");
  SetSampleTime(config.sample_time ? *config.sample_time : SampleTime::Continuous());
}

void Sine::CalcOutput(const BlockContext& c) const {
  c.y(0) = amplitude_ * std::sin(omega_ * c.time() + phase_) + bias_;
}

MB_REGISTER_BLOCK(Sine, BlockType{
    "sine", "y = amplitude·sin(2π·frequency_hz·t + phase) + bias. Continuous, or sampled with a sampleTime.",
    {Optional("amplitude", 1.0, "", "amplitude A"),
     Bounded("frequency_hz", 1.0, "Hz", "frequency f", 0.0, 1e12),
     Optional("phase", 0.0, "rad", "phase φ"),
     Optional("bias", 0.0, "", "offset b")},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<Sine>(c); }})

}  // namespace mb
