#include "blocks/time_periodic.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mb {

namespace {
Eigen::VectorXd Coefficients(const Parameters& p, const std::string& name, int harmonics) {
  Eigen::VectorXd c = p.Vector(name);
  if (c.size() == 0) return Eigen::VectorXd::Zero(harmonics);
  if (c.size() != harmonics) {
    throw std::invalid_argument(name + " has " + std::to_string(c.size()) + " entries; give one per harmonic (" +
                                std::to_string(harmonics) + ") or []");
  }
  return c;
}
}  // namespace

TimePeriodic::TimePeriodic(const BlockConfig& config)
    : Block(config.name),
      omega_(2.0 * std::numbers::pi * config.parameters.Number("frequency_hz")),
      cos_(Coefficients(config.parameters, "cos_coefficients", config.parameters.Integer("harmonics"))),
      sin_(Coefficients(config.parameters, "sin_coefficients", config.parameters.Integer("harmonics"))) {
  DeclareOutputPort("y");
  SetSampleTime(config.sample_time ? *config.sample_time : SampleTime::Continuous());
}

void TimePeriodic::CalcOutput(const BlockContext& c) const {
  double y = 0.0;
  for (Eigen::Index h = 0; h < cos_.size(); ++h) {
    const double theta = static_cast<double>(h + 1) * omega_ * c.time();
    y += cos_(h) * std::cos(theta) + sin_(h) * std::sin(theta);
  }
  c.y(0) = y;
}

MB_REGISTER_BLOCK(TimePeriodic, BlockType{
    "time_periodic",
    "y = Σ_h a_h cos(2πhft) + b_h sin(2πhft): a disturbance periodic in time (external vibration), linear in its "
    "coefficients. Continuous, or sampled with a sampleTime.",
    {Bounded("frequency_hz", 50.0, "Hz", "fundamental frequency f", 1e-9, 1e12),
     Bounded("harmonics", 1, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "", "a_1…a_H ([] = zeros)", ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "", "b_1…b_H ([] = zeros)", ParamType::kVector)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<TimePeriodic>(c); }})

}  // namespace mb
