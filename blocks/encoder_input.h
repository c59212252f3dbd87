#pragma once
// encoder_input: a HIL block — the position measured by an encoder channel of the I/O board attached for the
// run (hw/board_registry.h), in metres. Used in the I/O subsystem that replaces the plant under
// `motionblocks hil` (docs/hil.md).

#include "engine/block.h"
#include "engine/registry.h"
#include "hw/board.h"

namespace mb {

/// x[k] = counts[k] / counts_per_metre, counts[k] = the encoder count latched by the board at sample k
/// (zero-referenced when the board started). Ports: out "x" [m], out "counts" (the raw count).
/// Parameters: channel (board encoder channel, default 0), counts_per_metre [1/m] > 0 (default 1e7, a
/// 0.1 µm linear encoder). Discrete: sampleTime [Ts, offset] required (the HIL loop period).
/// CalcOutput is noexcept and allocation-free (reads the board's latched image).
/// @throws std::runtime_error if no board is attached (HIL blocks only run under `motionblocks hil`), or
/// std::invalid_argument if the board has no such channel.
class EncoderInput final : public Block {
 public:
  explicit EncoderInput(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const noexcept override;

 private:
  const IoBoard* board_;
  int channel_;
  double metres_per_count_;
};

}  // namespace mb
