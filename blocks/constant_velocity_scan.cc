#include "blocks/constant_velocity_scan.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mb {

namespace {

SmoothVelocityProfile MakeScan(const BlockConfig& config) {
  const auto& p = config.parameters;
  const Eigen::VectorXd speeds = p.Vector("velocities");
  const double stroke = p.Number("stroke");
  const double duration = p.Number("transition_duration");
  const double dwell = p.Number("dwell");
  std::vector<SmoothVelocityProfile::Transition> transitions;
  double t = p.Number("start_time");
  double direction = 1.0;
  for (Eigen::Index i = 0; i < speeds.size(); ++i) {
    const double v = speeds(i);
    if (!(v > 0.0) || v * duration > stroke) {
      throw std::invalid_argument(config.name + "/velocities/" + std::to_string(i) + ": " + std::to_string(v) +
                                  " m/s; each speed must be > 0 and at most stroke/transition_duration = " +
                                  std::to_string(stroke / duration) + " m/s");
    }
    const double cruise = (stroke - v * duration) / v;
    transitions.push_back({t, duration, direction * v});
    transitions.push_back({t + duration + cruise, duration, 0.0});
    t += 2.0 * duration + cruise + dwell;
    direction = -direction;
  }
  return SmoothVelocityProfile(p.Number("start_position"), std::move(transitions));
}

}  // namespace

ConstantVelocityScan::ConstantVelocityScan(const BlockConfig& config) : Block(config.name), profile_(MakeScan(config)) {
  DeclareOutputPort("position", 1, "m");
  DeclareOutputPort("velocity", 1, "m/s");
  DeclareOutputPort("acceleration", 1, "m/s^2");
  DeclareOutputPort("constant_velocity");
  if (config.sample_time) SetSampleTime(*config.sample_time);
}

void ConstantVelocityScan::CalcOutput(const BlockContext& c) const {
  profile_.Evaluate(c.time(), &c.y(0), &c.y(1), &c.y(2));
  c.y(3) = (c.y(2) == 0.0 && c.y(1) != 0.0) ? 1.0 : 0.0;
}

MB_REGISTER_BLOCK(ConstantVelocityScan, BlockType{
    "constant_velocity_scan",
    "Training scans (section 3.2): one stroke over `stroke` per velocity, alternating direction, half-sine "
    "transitions, dwell between strokes. Outputs position, velocity, acceleration, constant_velocity (0/1).",
    {Optional("velocities", nlohmann::json::array({0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5}), "m/s",
              "scan speeds v_1 … v_n (> 0)", ParamType::kVector),
     Bounded("stroke", 0.7, "m", "travel of each stroke", 1e-9, 1e6),
     Optional("start_position", 0.0, "m", "start of the first stroke (it moves in +x)"),
     Bounded("start_time", 0.1, "s", "time of the first transition", 0.0, 1e9),
     Bounded("transition_duration", 0.2, "s", "duration T of each half-sine transition", 1e-9, 1e6),
     Bounded("dwell", 0.3, "s", "rest between strokes", 0.0, 1e6)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<ConstantVelocityScan>(c); }})

}  // namespace mb
