#include "blocks/pd_controller.h"

#include <limits>
#include <stdexcept>

#include "engine/block_roles.h"

namespace mb {

PdController::PdController(const BlockConfig& config)
    : Block(config.name),
      kp_(config.parameters.Number("kp")),
      kd_(config.parameters.Number("kd")),
      filter_(config.parameters.Number("derivative_filter")) {
  const std::string& method = config.parameters.String("method");
  if (method != "backward_euler" && method != "tustin") {
    throw std::invalid_argument("method must be \"backward_euler\" or \"tustin\", got \"" + method + "\"");
  }
  DeclareInputPort("e");
  DeclareOutputPort("u");
  discrete_ = config.sample_time.has_value();
  if (!discrete_) {
    if (method != "backward_euler") {
      throw std::invalid_argument("method \"" + method + "\" discretises the controller: give a sampleTime [Ts, "
                                  "offset], or drop method for the continuous form");
    }
    if (!(filter_ > 0.0)) {
      throw std::invalid_argument("the continuous pd_controller needs derivative_filter > 0 s (K_d·s alone is "
                                  "improper); e.g. 1e-3, or give a sampleTime for the discrete form");
    }
    DeclareContinuousState(1);
    SetSampleTime(SampleTime::Continuous());
    return;
  }
  const double ts = config.sample_time->period;
  if (method == "tustin") {
    if (!(filter_ > 0.0)) {
      throw std::invalid_argument("method \"tustin\" needs derivative_filter > 0 s (its pole is at z = −1 for 0); "
                                  "use backward_euler for an unfiltered difference");
    }
    a_ = (2.0 * filter_ - ts) / (2.0 * filter_ + ts);
    b_ = 2.0 * kd_ / (2.0 * filter_ + ts);
  } else {
    a_ = filter_ / (filter_ + ts);
    b_ = kd_ / (filter_ + ts);
  }
  DeclareDiscreteState(2);  // e[k−1], d[k−1]
  SetSampleTime(*config.sample_time);
}

double PdController::FilteredDerivative(const BlockContext& c) const {
  const auto s = c.discrete_state();
  return a_ * s(1) + b_ * (c.u(0) - s(0));
}

void PdController::CalcOutput(const BlockContext& c) const {
  const double e = c.u(0);
  if (discrete_) {
    c.y(0) = kp_ * e + FilteredDerivative(c);
  } else {
    c.y(0) = kp_ * e + kd_ * (e - c.continuous_state()(0)) / filter_;
  }
}

void PdController::CalcDerivatives(const BlockContext& c) const {
  if (!discrete_) c.derivatives()(0) = (c.u(0) - c.continuous_state()(0)) / filter_;
}

void PdController::UpdateDiscrete(const BlockContext& c) const {
  const double d = FilteredDerivative(c);
  auto s = c.discrete_state();
  s(0) = c.u(0);
  s(1) = d;
}

MB_REGISTER_BLOCK(PdController, BlockType{
    "pd_controller",
    "u = K_p e + K_d·s/(T_f s + 1) e (paper eq. 3, filtered derivative); continuous, or discrete with a "
    "sampleTime (backward Euler or Tustin).",
    {Optional("kp", 0.0, "", "proportional gain K_p (N/m for position → force)"),
     Optional("kd", 0.0, "", "derivative gain K_d (N·s/m for position → force)"),
     Bounded("derivative_filter", 1e-3, "s", "derivative filter time constant T_f", 0.0,
             std::numeric_limits<double>::infinity()),
     Choice("method", "backward_euler", "discretisation: \"backward_euler\" or \"tustin\"",
            {"backward_euler", "tustin"})},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<PdController>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(PdController, "pd_controller", {"pd"})

}  // namespace mb
