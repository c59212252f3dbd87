#include "blocks/analog_output.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/block_roles.h"
#include "hw/board_registry.h"

namespace mb {

namespace {
IoBoard& AttachedBoard(const std::string& block) {
  IoBoard* board = BoardRegistry::Global().board();
  if (board == nullptr) {
    throw std::runtime_error(fmt::format(
        "analog_output '{}': no I/O board is attached; HIL blocks run only under `motionblocks hil … --board "
        "quanser|udp`, which opens the board first (to simulate, use the plant subsystem instead of the I/O "
        "subsystem)",
        block));
  }
  return *board;
}
}  // namespace

AnalogOutput::AnalogOutput(const BlockConfig& config)
    : Block(config.name),
      board_(&AttachedBoard(config.name)),
      channel_(config.parameters.Integer("channel")),
      volts_per_newton_(1.0 / config.parameters.Number("newtons_per_volt")),
      limit_(config.parameters.Number("limit")) {
  if (channel_ >= board_->num_analog_outputs()) {
    throw std::invalid_argument(fmt::format("analog_output '{}': channel {} does not exist on {} (it has {} analog "
                                            "outputs)",
                                            config.name, channel_, board_->description(),
                                            board_->num_analog_outputs()));
  }
  DeclareInputPort("f", 1, "N", /*direct_feedthrough=*/true);
  DeclareOutputPort("voltage", 1, "V");
  SetSampleTime(*config.sample_time);
}

void AnalogOutput::CalcOutput(const BlockContext& c) const noexcept {
  const double f = c.u(0);
  const double v = std::isfinite(f) ? std::clamp(f * volts_per_newton_, -limit_, limit_) : 0.0;
  c.y(0) = v;
  board_->SetAnalogOutput(channel_, v);
}

MB_REGISTER_BLOCK(AnalogOutput, BlockType{
    "analog_output",
    "HIL: v = clamp(f / newtons_per_volt, ±limit) written to analog output `channel` of the attached I/O board "
    "after each controller step (non-finite f → 0 V). In: f [N]; out: voltage [V]. Discrete (sampleTime = the "
    "HIL loop period); runs only under `motionblocks hil`.",
    {Bounded("channel", 0, "", "board analog output channel", 0, kMaxAnalogOutputs - 1, ParamType::kInteger),
     Bounded("newtons_per_volt", 10.0, "N/V", "force per volt of the amplifier and motor", 1e-9,
             std::numeric_limits<double>::infinity()),
     Bounded("limit", 10.0, "V", "output clamp: |v| ≤ limit", 1e-9, std::numeric_limits<double>::infinity())},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<AnalogOutput>(c); }})

// A board channel (engine/block_roles.h; hw/virtual_stage.h reads the I/O subsystem by it).
MB_REGISTER_IO_CHANNEL(AnalogOutput, "analog_output", IoChannelTrait{false, "newtons_per_volt", "limit"})

}  // namespace mb
