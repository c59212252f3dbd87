#include "blocks/paper_trajectory.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mb {

SmoothVelocityProfile::SmoothVelocityProfile(double start_position, std::vector<Transition> transitions)
    : start_position_(start_position), transitions_(std::move(transitions)) {
  double x = start_position_, v = 0.0, t_free = -1e300;
  for (std::size_t i = 0; i < transitions_.size(); ++i) {
    const Transition& tr = transitions_[i];
    if (!(tr.duration > 0.0) || !std::isfinite(tr.start_time) || !std::isfinite(tr.target_velocity)) {
      throw std::invalid_argument("velocity profile: transition " + std::to_string(i) +
                                  " needs a positive duration and finite start time and velocity");
    }
    if (tr.start_time < t_free - 1e-12) {
      throw std::invalid_argument("velocity profile: transition " + std::to_string(i) + " starts at " +
                                  std::to_string(tr.start_time) + " s, before the previous one ends (" +
                                  std::to_string(t_free) + " s); order the starts and leave room for the durations");
    }
    if (i > 0) x += v * (tr.start_time - t_free);
    position_at_start_.push_back(x);
    velocity_before_.push_back(v);
    x += v * tr.duration + (tr.target_velocity - v) * tr.duration / 2.0;
    v = tr.target_velocity;
    t_free = tr.start_time + tr.duration;
  }
}

double SmoothVelocityProfile::end_time() const noexcept {
  return transitions_.empty() ? 0.0 : transitions_.back().start_time + transitions_.back().duration;
}

void SmoothVelocityProfile::Evaluate(double t, double* position, double* velocity,
                                     double* acceleration) const noexcept {
  if (transitions_.empty() || t <= transitions_.front().start_time) {
    *position = start_position_;
    *velocity = 0.0;
    *acceleration = 0.0;
    return;
  }
  // The last transition that has started (few transitions: a linear scan is fastest).
  std::size_t i = 0;
  while (i + 1 < transitions_.size() && transitions_[i + 1].start_time <= t) ++i;
  const Transition& tr = transitions_[i];
  const double v0 = velocity_before_[i];
  const double dv = tr.target_velocity - v0;
  const double tau = t - tr.start_time;
  if (tau >= tr.duration) {
    *velocity = tr.target_velocity;
    *acceleration = 0.0;
    *position = position_at_start_[i] + v0 * tr.duration + dv * tr.duration / 2.0 +
                tr.target_velocity * (tau - tr.duration);
    return;
  }
  const double theta = std::numbers::pi * tau / tr.duration;
  *acceleration = dv * std::numbers::pi / (2.0 * tr.duration) * std::sin(theta);
  *velocity = v0 + dv * (1.0 - std::cos(theta)) / 2.0;
  *position = position_at_start_[i] + v0 * tau + dv / 2.0 * (tau - tr.duration / std::numbers::pi * std::sin(theta));
}

namespace {

SmoothVelocityProfile MakeProfile(const BlockConfig& config) {
  const auto& p = config.parameters;
  const Eigen::VectorXd v = p.Vector("velocities");
  const Eigen::VectorXd starts = p.Vector("transition_starts");
  const Eigen::VectorXd durations = p.Vector("transition_duration");
  if (starts.size() != v.size()) {
    throw std::invalid_argument(config.name + ": transition_starts has " + std::to_string(starts.size()) +
                                " entries but velocities has " + std::to_string(v.size()) + "; give one start per "
                                "velocity");
  }
  if (durations.size() != 1 && durations.size() != v.size()) {
    throw std::invalid_argument(config.name + ": transition_duration needs 1 or " + std::to_string(v.size()) +
                                " entries");
  }
  std::vector<SmoothVelocityProfile::Transition> transitions;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    transitions.push_back({starts(i), durations.size() == 1 ? durations(0) : durations(i), v(i)});
  }
  return SmoothVelocityProfile(p.Number("start_position"), std::move(transitions));
}

}  // namespace

PaperTrajectory::PaperTrajectory(const BlockConfig& config)
    : Block(config.name), profile_(MakeProfile(config)), time_advance_(config.parameters.Number("time_advance")) {
  DeclareOutputPort("position", 1, "m");
  DeclareOutputPort("velocity", 1, "m/s");
  DeclareOutputPort("acceleration", 1, "m/s^2");
  if (config.sample_time) SetSampleTime(*config.sample_time);
}

void PaperTrajectory::CalcOutput(const BlockContext& c) const {
  profile_.Evaluate(c.time() + time_advance_, &c.y(0), &c.y(1), &c.y(2));
}

MB_REGISTER_BLOCK(PaperTrajectory, BlockType{
    "paper_trajectory",
    "Reference of the paper's Fig. 9: 0 → 600 mm, 150 and 350 mm/s, half-sine acceleration over 0–0.2, "
    "1.2–1.4 and 2.4–2.6 s. Outputs position, velocity, acceleration. Sample time optional.",
    {Optional("start_position", 0.0, "m", "position before the first transition"),
     Optional("velocities", nlohmann::json::array({0.15, 0.35, 0.0}), "m/s", "velocity after each transition",
              ParamType::kVector),
     Optional("transition_starts", nlohmann::json::array({0.0, 1.2, 2.4}), "s", "start time of each transition",
              ParamType::kVector),
     Optional("transition_duration", 0.2, "s", "duration of each transition (one value or one per transition)",
              ParamType::kVector),
     Bounded("time_advance", 0.0, "s",
             "outputs the profile at t + time_advance (Ts/2 for a held feedforward: mid-interval sampling)", 0.0, 1e6)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<PaperTrajectory>(c); }})

}  // namespace mb
