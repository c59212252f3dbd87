#pragma once
// analog_output: a HIL block — a force command sent to the amplifier through an analog output of the I/O
// board attached for the run (hw/board_registry.h), as a clamped voltage. Used in the I/O subsystem that
// replaces the plant under `motionblocks hil` (docs/hil.md).

#include "engine/block.h"
#include "engine/registry.h"
#include "hw/board.h"

namespace mb {

/// v[k] = clamp(f[k] / newtons_per_volt, −limit, limit), written to analog output `channel` after the
/// controller step of sample k (a non-finite f gives 0 V). Port: in "f" [N] (feeds through), out "voltage" [V]
/// (the value sent). Parameters: channel (default 0), newtons_per_volt [N/V] > 0 (the amplifier and motor's
/// force constant, default 10), limit [V] > 0 (the output clamp, default 10). Discrete: sampleTime required.
/// CalcOutput is noexcept and allocation-free (buffers the voltage in the board's output image; the HIL loop
/// writes it).
/// @throws std::runtime_error if no board is attached, std::invalid_argument if the board has no such channel.
class AnalogOutput final : public Block {
 public:
  explicit AnalogOutput(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const noexcept override;

 private:
  IoBoard* board_;
  int channel_;
  double volts_per_newton_;
  double limit_;
};

}  // namespace mb
