#include "hw/udp_protocol.h"

#include <bit>
#include <cstring>

namespace mb {

namespace {

// Little-endian field access, independent of the host's byte order.
template <typename T>
void Put(std::byte* at, T value) noexcept {
  using U = std::conditional_t<sizeof(T) == 8, std::uint64_t,
                               std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint16_t>>;
  const U bits = std::bit_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(U); ++i) at[i] = static_cast<std::byte>((bits >> (8 * i)) & 0xFFu);
}

template <typename T>
T Get(const std::byte* at) noexcept {
  using U = std::conditional_t<sizeof(T) == 8, std::uint64_t,
                               std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint16_t>>;
  U bits = 0;
  for (std::size_t i = 0; i < sizeof(U); ++i) bits = static_cast<U>(bits | (static_cast<U>(at[i]) << (8 * i)));
  return std::bit_cast<T>(bits);
}

constexpr std::size_t kOffsetMagic = 0;
constexpr std::size_t kOffsetVersion = 4;
constexpr std::size_t kOffsetType = 6;
constexpr std::size_t kOffsetSequence = 8;
constexpr std::size_t kOffsetTimestamp = 12;
constexpr std::size_t kOffsetDigital = 20;
constexpr std::size_t kOffsetCounts = 24;
constexpr std::size_t kOffsetVolts = kOffsetCounts + 4 * kMaxEncoderChannels;
static_assert(kOffsetVolts + 8 * kMaxAnalogOutputs + 8 == kPacketSize, "wire format and kPacketSize disagree");

}  // namespace

void EncodePacket(const BoardPacket& p, PacketBytes* bytes) noexcept {
  std::byte* b = bytes->data();
  std::memset(b, 0, kPacketSize);
  Put(b + kOffsetMagic, kProtocolMagic);
  Put(b + kOffsetVersion, kProtocolVersion);
  Put(b + kOffsetType, static_cast<std::uint16_t>(p.type));
  Put(b + kOffsetSequence, p.sequence);
  Put(b + kOffsetTimestamp, p.timestamp_ns);
  Put(b + kOffsetDigital, p.digital);
  for (std::size_t i = 0; i < p.encoder_counts.size(); ++i) Put(b + kOffsetCounts + 4 * i, p.encoder_counts[i]);
  for (std::size_t i = 0; i < p.analog_volts.size(); ++i) Put(b + kOffsetVolts + 8 * i, p.analog_volts[i]);
}

bool DecodePacket(const std::byte* b, std::size_t size, BoardPacket* p) noexcept {
  if (size != kPacketSize) return false;
  if (Get<std::uint32_t>(b + kOffsetMagic) != kProtocolMagic) return false;
  if (Get<std::uint16_t>(b + kOffsetVersion) != kProtocolVersion) return false;
  const auto type = Get<std::uint16_t>(b + kOffsetType);
  if (type < static_cast<std::uint16_t>(PacketType::kSampleRequest) ||
      type > static_cast<std::uint16_t>(PacketType::kOutputs)) {
    return false;
  }
  p->type = static_cast<PacketType>(type);
  p->sequence = Get<std::uint32_t>(b + kOffsetSequence);
  p->timestamp_ns = Get<std::int64_t>(b + kOffsetTimestamp);
  p->digital = Get<std::uint32_t>(b + kOffsetDigital);
  for (std::size_t i = 0; i < p->encoder_counts.size(); ++i) {
    p->encoder_counts[i] = Get<std::int32_t>(b + kOffsetCounts + 4 * i);
  }
  for (std::size_t i = 0; i < p->analog_volts.size(); ++i) p->analog_volts[i] = Get<double>(b + kOffsetVolts + 8 * i);
  return true;
}

}  // namespace mb
