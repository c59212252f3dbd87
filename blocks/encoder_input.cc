#include "blocks/encoder_input.h"

#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/block_roles.h"
#include "hw/board_registry.h"

namespace mb {

namespace {
const IoBoard& AttachedBoard(const std::string& block, const char* type) {
  const IoBoard* board = BoardRegistry::Global().board();
  if (board == nullptr) {
    throw std::runtime_error(fmt::format(
        "{} '{}': no I/O board is attached; HIL blocks run only under `motionblocks hil … --board quanser|udp`, "
        "which opens the board first (to simulate, use the plant subsystem instead of the I/O subsystem)",
        type, block));
  }
  return *board;
}
}  // namespace

EncoderInput::EncoderInput(const BlockConfig& config)
    : Block(config.name),
      board_(&AttachedBoard(config.name, "encoder_input")),
      channel_(config.parameters.Integer("channel")),
      metres_per_count_(1.0 / config.parameters.Number("counts_per_metre")) {
  if (channel_ >= board_->num_encoder_channels()) {
    throw std::invalid_argument(fmt::format("encoder_input '{}': channel {} does not exist on {} (it has {} encoder "
                                            "channels, 0–{})",
                                            config.name, channel_, board_->description(),
                                            board_->num_encoder_channels(), board_->num_encoder_channels() - 1));
  }
  DeclareOutputPort("x", 1, "m");
  DeclareOutputPort("counts", 1, "");
  SetSampleTime(*config.sample_time);
}

void EncoderInput::CalcOutput(const BlockContext& c) const noexcept {
  const std::int32_t counts = board_->encoder_counts(channel_);
  c.y(0) = static_cast<double>(counts) * metres_per_count_;
  c.y(1) = static_cast<double>(counts);
}

MB_REGISTER_BLOCK(EncoderInput, BlockType{
    "encoder_input",
    "HIL: x = counts / counts_per_metre from encoder `channel` of the attached I/O board (latched at each sample, "
    "zero at start). Outs: x [m], counts. Discrete (sampleTime = the HIL loop period); runs only under "
    "`motionblocks hil`.",
    {Bounded("channel", 0, "", "board encoder channel", 0, kMaxEncoderChannels - 1, ParamType::kInteger),
     Bounded("counts_per_metre", 1e7, "1/m", "encoder resolution: counts per metre of travel", 1e-9,
             std::numeric_limits<double>::infinity())},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<EncoderInput>(c); }})

// A board channel (engine/block_roles.h; hw/virtual_stage.h reads the I/O subsystem by it).
MB_REGISTER_IO_CHANNEL(EncoderInput, "encoder_input", IoChannelTrait{true, "counts_per_metre", ""})

}  // namespace mb
