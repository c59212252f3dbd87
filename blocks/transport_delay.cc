#include "blocks/transport_delay.h"

#include <cmath>
#include <stdexcept>
#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

namespace {
// Discrete state layout: [count, head, buffer_0 … buffer_{K−1}].
constexpr Eigen::Index kCount = 0, kHead = 1, kBuffer = 2;

double SamplePeriod(const BlockConfig& config) {
  if (!config.sample_time) {
    throw std::invalid_argument("transport_delay '" + config.name + "' needs a sampleTime [Ts, offset]");
  }
  return config.sample_time->period;
}
}  // namespace

TransportDelay::TransportDelay(const BlockConfig& config) : Block(config.name) {
  const double ts = SamplePeriod(config);
  const double samples = config.parameters.Number("delay") / ts;
  if (!(samples >= 0.0 && samples <= 1e6)) {
    throw std::invalid_argument("transport_delay '" + config.name + "': delay/Ts = " + std::to_string(samples) +
                                " samples; it must lie in [0, 1e6] (use a coarser sampleTime for long delays)");
  }
  // A delay within 1e-9 samples of a whole number is that number (d = 4 ms at Ts = 1 ms is 4 samples exactly).
  const double rounded = std::round(samples);
  const double k = std::abs(samples - rounded) < 1e-9 ? rounded : std::floor(samples);
  whole_ = static_cast<Eigen::Index>(k);
  fraction_ = std::max(0.0, samples - k);
  capacity_ = whole_ + 1;
  // u feeds through: for d < Ts, and at the first hit, where the first sample is held.
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("y");
  DeclareDiscreteState(static_cast<int>(kBuffer + capacity_));
  SetSampleTime(*config.sample_time);
}

double TransportDelay::Past(const BlockContext& c, Eigen::Index j, double current) const {
  const auto x = c.discrete_state();
  const auto count = static_cast<Eigen::Index>(x(kCount));
  if (j == 0 || count == 0) return current;
  const Eigen::Index back = std::min(j, count) - 1;  // 0 = the newest stored sample u[n − 1]
  const auto head = static_cast<Eigen::Index>(x(kHead));
  return x(kBuffer + (head - back + capacity_) % capacity_);
}

void TransportDelay::CalcOutput(const BlockContext& c) const {
  const double current = c.u(0);
  const double newer = Past(c, whole_, current);
  const double older = Past(c, whole_ + 1, current);
  c.y(0) = (1.0 - fraction_) * newer + fraction_ * older;
}

void TransportDelay::UpdateDiscrete(const BlockContext& c) const {
  auto x = c.discrete_state();
  const auto head = (static_cast<Eigen::Index>(x(kHead)) + 1) % capacity_;
  x(kHead) = static_cast<double>(head);
  x(kBuffer + head) = c.u(0);
  x(kCount) = std::min(x(kCount) + 1.0, static_cast<double>(capacity_));
}

MB_REGISTER_BLOCK(TransportDelay, BlockType{
    "transport_delay",
    "y(t) = u(t − d): pure delay, discrete (needs sampleTime [Ts, offset]), linear interpolation for a "
    "fractional d/Ts; before the first sample the input is held at its first value. In: u; out: y.",
    {Bounded("delay", 0.0, "s", "delay d", 0.0, 1000.0)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<TransportDelay>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect time_delay (models/diagnosis/effects/time_delay.cc) to a diagram.
EffectBlockTemplate TimeDelayEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "transport_delay";
  block.element_name = "delay";
  block.placement = BlockPlacement::kInsertBeforeOutput;
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) {
    const double delay = BlockParameter(d, "delay");
    if (delay < 0.0) {
      throw std::invalid_argument(fmt::format(
          "{} of {:.4g} ms is negative: the model lags the measurement, which is an actuator lag (the command "
          "acts later than logged: effect actuator_lag) or a time-stamp offset; a transport_delay block cannot "
          "advance the output",
          d.effect, delay * 1e3));
    }
    return nlohmann::json{{"delay", WithUnit(delay, "s")}};
  };
  block.free = {"delay"};
  return block;
}

// Adds the diagnosed effect actuator_lag (models/diagnosis/effects/actuator_lag.cc): the delay on the command path,
// between the logged command and the force that acts (BlockPlacement::kOnCommand).
EffectBlockTemplate ActuatorLagEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "transport_delay";
  block.element_name = "actuator_lag";
  block.placement = BlockPlacement::kOnCommand;
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) {
    const double lag = BlockParameter(d, "lag");
    if (!(lag > 0.0)) {
      throw std::invalid_argument(fmt::format("{} of {:.4g} ms: a lag must be positive", d.effect, lag * 1e3));
    }
    return nlohmann::json{{"delay", WithUnit(lag, "s")}};
  };
  // The lag as the diagnosis found it is the start of the diagram's own fit: in simulation mode it was scanned through
  // the loop linearised along the record, which the full closed-loop diagram refines (the output-error model's last
  // step: Ljung, System Identification, 2nd ed., §7.3).
  block.refinable = {"delay"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(time_delay, TimeDelayEffectBlock())
MB_REGISTER_EFFECT_BLOCK(actuator_lag, ActuatorLagEffectBlock())

}  // namespace mb
