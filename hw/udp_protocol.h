#pragma once
// The board protocol of the UDP virtual board (docs/hil.md, "Protocol"): fixed-size datagrams on 127.0.0.1
// between the HIL loop (client, hw/udp_board.h) and the virtual stage (server, hw/virtual_stage.h).
//
// One exchange per sample instant k:
//   client → stage  kSampleRequest {sequence k}                       "latch your encoders now"
//   stage → client  kSample        {sequence k, encoder counts, digital inputs}
//   client → stage  kOutputs       {sequence k, analog volts, digital outputs}   after the controller step
// The stage answers every request at once with the counts of its plant at that instant and applies the
// outputs the moment they arrive (zero-order hold). Sequence numbers let the client drop late replies (a
// reply to an older request is a miss for the current sample) and the stage count lost packets.
//
// Wire format, all fields little-endian, no padding (kPacketSize = 128 bytes):
//   offset  size  field
//        0     4  magic  0x4D424856 ("VHBM" on the wire)
//        4     2  version (kProtocolVersion)
//        6     2  type (PacketType)
//        8     4  sequence (uint32, wraps)
//       12     8  timestamp_ns (int64, sender's CLOCK_MONOTONIC; client and stage share the machine)
//       20     4  digital (uint32 bit set: inputs in kSample, outputs in kOutputs)
//       24    32  encoder_counts[8] (int32)            meaningful in kSample
//       56    64  analog_volts[8] (IEEE-754 binary64)  meaningful in kOutputs
//      120     8  reserved (zero)

#include <array>
#include <cstddef>
#include <cstdint>

#include "hw/board.h"

namespace mb {

inline constexpr std::uint32_t kProtocolMagic = 0x4D424856;
inline constexpr std::uint16_t kProtocolVersion = 1;
inline constexpr std::size_t kPacketSize = 128;

enum class PacketType : std::uint16_t {
  kSampleRequest = 1,  ///< client → stage
  kSample = 2,         ///< stage → client
  kOutputs = 3,        ///< client → stage
};

/// One datagram, decoded.
struct BoardPacket {
  PacketType type = PacketType::kSampleRequest;
  std::uint32_t sequence = 0;
  std::int64_t timestamp_ns = 0;
  std::uint32_t digital = 0;
  std::array<std::int32_t, kMaxEncoderChannels> encoder_counts{};
  std::array<double, kMaxAnalogOutputs> analog_volts{};
};

using PacketBytes = std::array<std::byte, kPacketSize>;

/// Serialises `packet` in the wire format above. noexcept, no allocation.
void EncodePacket(const BoardPacket& packet, PacketBytes* bytes) noexcept;
/// Parses `size` received bytes. Returns false (and leaves `packet` unspecified) unless the size, magic,
/// version and type are right. noexcept, no allocation.
bool DecodePacket(const std::byte* bytes, std::size_t size, BoardPacket* packet) noexcept;

}  // namespace mb
