#pragma once
// The I/O-board interface of the hardware-in-the-loop path (docs/hil.md): encoder inputs, analog outputs,
// digital I/O and the board's sample clock. Backends: QuanserBoard (hw/quanser_board.h, the Quanser HIL C API,
// built with WITH_QUANSER) and UdpBoard (hw/udp_board.h, the virtual stage on loopback).
//
// The board keeps an input/output image: WaitForSample() latches the inputs of one sample instant into it,
// the HIL blocks (blocks/encoder_input.h, blocks/analog_output.h) read and write the image while the
// controller runs, WriteOutputs() sends the buffered outputs. Everything called inside the real-time loop is
// noexcept and allocation-free; only Start() may allocate or throw.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>

namespace mb {

/// Channel counts of the board image (the UDP protocol carries exactly these; Quanser boards have ≤ 8 of each).
inline constexpr int kMaxEncoderChannels = 8;
inline constexpr int kMaxAnalogOutputs = 8;
inline constexpr int kMaxDigitalChannels = 32;  ///< digital inputs and outputs are bits of a 32-bit word

/// What one sample instant brought.
enum class SampleStatus {
  kOk,      ///< fresh inputs for this sample instant
  kMissed,  ///< no fresh inputs (reply timed out, lost or arrived late): the image holds the previous ones
  kFault,   ///< the board reported an error; the loop must stop
};

/// Timing of one sample instant, CLOCK_MONOTONIC nanoseconds.
struct SampleTiming {
  std::int64_t scheduled_ns = 0;  ///< when the sample was due (start + k·period)
  std::int64_t wake_ns = 0;       ///< when the loop woke up for it (the inputs were latched right after)
};

/// An I/O board with a sample clock. Not copyable; one loop drives it from one thread.
class IoBoard {
 public:
  IoBoard() = default;
  virtual ~IoBoard() = default;
  IoBoard(const IoBoard&) = delete;
  IoBoard& operator=(const IoBoard&) = delete;

  /// Short description for logs and summaries, e.g. "udp 127.0.0.1:40123" or "quanser q8_usb 0".
  virtual std::string description() const = 0;
  /// Channels this board provides (channel numbers 0 … n−1).
  virtual int num_encoder_channels() const = 0;
  virtual int num_analog_outputs() const = 0;

  /// Starts the sample clock at `period` [s] with the encoder counts zero-referenced at this instant (as
  /// hil_set_encoder_counts(0) does). The first sample instant is start + period. May allocate.
  /// @throws std::runtime_error naming the board and what to check (cable, driver, virtual stage running).
  virtual void Start(double period) = 0;
  /// Blocks until the next sample instant of the board's clock and latches encoder counts and digital inputs
  /// into the image. Real time: noexcept, no allocation.
  virtual SampleStatus WaitForSample(SampleTiming* timing) noexcept = 0;
  /// Sends the buffered analog and digital outputs. Returns false on a board error. Real time.
  virtual bool WriteOutputs() noexcept = 0;
  /// Safe stop: zeroes every analog and digital output, writes them, stops the clock. Idempotent, noexcept.
  virtual void SafeStop() noexcept = 0;

  /// Latched encoder count of `channel` (0 ≤ channel < kMaxEncoderChannels) [counts].
  std::int32_t encoder_counts(int channel) const noexcept { return encoder_counts_[Index(channel)]; }
  /// Latched digital inputs, bit i = channel i.
  std::uint32_t digital_inputs() const noexcept { return digital_inputs_; }
  /// Buffers the voltage of analog output `channel` [V] (sent by WriteOutputs). Non-finite values become 0.
  void SetAnalogOutput(int channel, double volts) noexcept {
    analog_outputs_[Index(channel)] = std::isfinite(volts) ? volts : 0.0;
  }
  double analog_output(int channel) const noexcept { return analog_outputs_[Index(channel)]; }
  /// Buffers the digital outputs, bit i = channel i (sent by WriteOutputs).
  void SetDigitalOutputs(std::uint32_t bits) noexcept { digital_outputs_ = bits; }
  std::uint32_t digital_outputs() const noexcept { return digital_outputs_; }

 protected:
  static std::size_t Index(int channel) noexcept { return static_cast<std::size_t>(channel); }
  void ZeroOutputImage() noexcept {
    analog_outputs_.fill(0.0);
    digital_outputs_ = 0;
  }

  std::array<std::int32_t, kMaxEncoderChannels> encoder_counts_{};
  std::uint32_t digital_inputs_ = 0;
  std::array<double, kMaxAnalogOutputs> analog_outputs_{};
  std::uint32_t digital_outputs_ = 0;
};

}  // namespace mb
