#include "blocks/velocity_dependent_ripple.h"

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

VelocityDependentRipple::VelocityDependentRipple(const BlockConfig& config)
    : Block(config.name),
      wavenumber_(2.0 * std::numbers::pi / config.parameters.Number("period")),
      offset_(config.parameters.Number("position_offset")),
      cos_(Coefficients(config.parameters, "cos_coefficients", config.parameters.Integer("harmonics"))),
      sin_(Coefficients(config.parameters, "sin_coefficients", config.parameters.Integer("harmonics"))) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  DeclareOutputPort("y");
}

void VelocityDependentRipple::CalcOutput(const BlockContext& c) const {
  const double theta = wavenumber_ * (c.u(0) - offset_);
  const double c1 = std::cos(theta), s1 = std::sin(theta);
  double ch = c1, sh = s1, y = 0.0;
  for (Eigen::Index h = 0; h < cos_.size(); ++h) {
    y += cos_(h) * ch + sin_(h) * sh;
    const double next_c = ch * c1 - sh * s1;
    sh = sh * c1 + ch * s1;
    ch = next_c;
  }
  c.y(0) = std::abs(c.u(1)) * y;
}

MB_REGISTER_BLOCK(VelocityDependentRipple, BlockType{
    "velocity_dependent_ripple",
    "y = |v|·Σ_h a_h cos(2πh(x−x₀)/P) + b_h sin(2πh(x−x₀)/P): position-periodic ripple whose amplitude grows "
    "with speed. In: x [m], v [m/s].",
    {Bounded("period", 0.0225, "m", "spatial period P (pole pitch, screw lead)", 1e-9, 1e9),
     Bounded("harmonics", 1, "", "number of harmonics H", 1, 200, ParamType::kInteger),
     Optional("cos_coefficients", nlohmann::json::array(), "", "a_1…a_H per unit speed ([] = zeros)",
              ParamType::kVector),
     Optional("sin_coefficients", nlohmann::json::array(), "", "b_1…b_H per unit speed ([] = zeros)",
              ParamType::kVector),
     Optional("position_offset", 0.0, "m", "x₀: position reference of the ripple (encoder zero of the record)")},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<VelocityDependentRipple>(c); }})

}  // namespace mb
