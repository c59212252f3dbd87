#pragma once
// The UDP virtual board: an IoBoard whose "hardware" is a virtual stage process (`motionblocks virtual-stage`,
// hw/virtual_stage.h) on 127.0.0.1, spoken to in the protocol of hw/udp_protocol.h. The sample clock is this
// process's: clock_nanosleep on an absolute schedule (hw/realtime.h).

#include <cstdint>
#include <memory>
#include <string>

#include "hw/board.h"
#include "hw/udp_socket.h"

namespace mb {

struct UdpBoardOptions {
  std::uint16_t stage_port = 0;   ///< the virtual stage's port on 127.0.0.1
  double reply_timeout = 0.5e-3;  ///< how long a sample waits for the stage's reply [s]; then it is a miss
  double connect_timeout = 2.0;   ///< how long Start waits for the stage's first reply [s]
};

class UdpBoard final : public IoBoard {
 public:
  /// Opens a socket on an ephemeral loopback port. @throws std::runtime_error if that fails.
  explicit UdpBoard(UdpBoardOptions options);

  std::string description() const override;
  int num_encoder_channels() const override { return kMaxEncoderChannels; }
  int num_analog_outputs() const override { return kMaxAnalogOutputs; }

  /// Exchanges a first sample with the stage (zero-referencing the encoder counts), sets the schedule
  /// t_k = now + k·period. @throws std::runtime_error if the stage does not answer within connect_timeout.
  void Start(double period) override;
  /// Sleeps until t_k, asks the stage for its encoders and waits up to reply_timeout for the reply with
  /// sequence k. Late replies to older requests are dropped. kMissed holds the previous counts.
  SampleStatus WaitForSample(SampleTiming* timing) noexcept override;
  /// Sends the outputs with sequence k. False if the kernel refused the datagram.
  bool WriteOutputs() noexcept override;
  void SafeStop() noexcept override;

  /// Replies dropped because they answered an older request (seen so far).
  long long late_replies() const { return late_replies_; }

 private:
  UdpBoardOptions options_;
  LoopbackUdpSocket socket_;
  std::int64_t period_ns_ = 0;
  std::int64_t start_ns_ = 0;
  std::uint32_t sequence_ = 0;  // of the last request sent
  std::int64_t tick_ = 0;       // sample instants since Start
  std::array<std::int32_t, kMaxEncoderChannels> zero_counts_{};
  long long late_replies_ = 0;
  bool running_ = false;
};

}  // namespace mb
