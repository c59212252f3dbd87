#include "hw/udp_board.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "hw/realtime.h"

namespace mb {

namespace {
std::int64_t Nanoseconds(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e9)); }
}  // namespace

UdpBoard::UdpBoard(UdpBoardOptions options) : options_(options), socket_(0) {
  if (options_.stage_port == 0) {
    throw std::invalid_argument("UDP board: give the virtual stage's port (--port, printed by `motionblocks "
                                "virtual-stage` when it starts)");
  }
  if (!(options_.reply_timeout > 0.0) || !(options_.connect_timeout > 0.0)) {
    throw std::invalid_argument("UDP board: reply and connect timeouts must be > 0 s");
  }
}

std::string UdpBoard::description() const { return fmt::format("udp 127.0.0.1:{}", options_.stage_port); }

void UdpBoard::Start(double period) {
  if (!(period > 0.0)) throw std::invalid_argument(fmt::format("UDP board: sample period {} s must be > 0", period));
  period_ns_ = Nanoseconds(period);
  const std::int64_t deadline = MonotonicNanoseconds() + Nanoseconds(options_.connect_timeout);
  // Ask repeatedly (a datagram may be lost) until the first sample arrives.
  BoardPacket request;
  request.type = PacketType::kSampleRequest;
  BoardPacket reply;
  bool connected = false;
  while (!connected && MonotonicNanoseconds() < deadline) {
    ++sequence_;
    request.sequence = sequence_;
    request.timestamp_ns = MonotonicNanoseconds();
    socket_.SendTo(options_.stage_port, request);
    const std::int64_t retry = std::min(deadline, MonotonicNanoseconds() + 100'000'000);
    while (MonotonicNanoseconds() < retry && socket_.ReceiveUntil(retry, &reply)) {
      if (reply.type == PacketType::kSample && reply.sequence == sequence_) {
        connected = true;
        break;
      }
    }
  }
  if (!connected) {
    throw std::runtime_error(fmt::format("UDP board: no virtual stage answers on 127.0.0.1:{} within {} s; start "
                                         "`motionblocks virtual-stage PLANT.json --io HIL_IO.json --port {}` first",
                                         options_.stage_port, options_.connect_timeout, options_.stage_port));
  }
  zero_counts_ = reply.encoder_counts;
  encoder_counts_.fill(0);
  digital_inputs_ = reply.digital;
  ZeroOutputImage();
  // Sequence numbers continue after the handshake's, so a late handshake reply never passes for a sample.
  tick_ = 0;
  start_ns_ = MonotonicNanoseconds();
  running_ = true;
}

SampleStatus UdpBoard::WaitForSample(SampleTiming* timing) noexcept {
  if (!running_) return SampleStatus::kFault;
  ++sequence_;
  ++tick_;
  timing->scheduled_ns = start_ns_ + tick_ * period_ns_;
  SleepUntil(timing->scheduled_ns);
  timing->wake_ns = MonotonicNanoseconds();
  BoardPacket packet;
  packet.type = PacketType::kSampleRequest;
  packet.sequence = sequence_;
  packet.timestamp_ns = timing->wake_ns;
  if (!socket_.SendTo(options_.stage_port, packet)) return SampleStatus::kMissed;
  const std::int64_t deadline = timing->wake_ns + Nanoseconds(options_.reply_timeout);
  while (socket_.ReceiveUntil(deadline, &packet)) {
    if (packet.type != PacketType::kSample) continue;
    if (packet.sequence != sequence_) {
      ++late_replies_;
      continue;
    }
    for (std::size_t i = 0; i < encoder_counts_.size(); ++i) {
      // Two's-complement wrap, as a hardware counter does.
      encoder_counts_[i] = static_cast<std::int32_t>(static_cast<std::uint32_t>(packet.encoder_counts[i]) -
                                                     static_cast<std::uint32_t>(zero_counts_[i]));
    }
    digital_inputs_ = packet.digital;
    return SampleStatus::kOk;
  }
  return SampleStatus::kMissed;
}

bool UdpBoard::WriteOutputs() noexcept {
  if (!running_) return false;
  BoardPacket packet;
  packet.type = PacketType::kOutputs;
  packet.sequence = sequence_;
  packet.timestamp_ns = MonotonicNanoseconds();
  packet.digital = digital_outputs_;
  packet.analog_volts = analog_outputs_;
  return socket_.SendTo(options_.stage_port, packet);
}

void UdpBoard::SafeStop() noexcept {
  ZeroOutputImage();
  if (!running_) return;
  // Sent twice: a single lost datagram must not leave the stage driven (its watchdog is the last resort).
  WriteOutputs();
  WriteOutputs();
  running_ = false;
}

}  // namespace mb
