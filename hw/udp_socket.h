#pragma once
// A UDP socket on the loopback interface only (127.0.0.1): the virtual board never listens on or sends to any
// other address. RAII around the file descriptor; Send/Receive are noexcept and allocation-free.

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>

#include "hw/udp_protocol.h"

namespace mb {

class LoopbackUdpSocket {
 public:
  /// Opens a socket bound to 127.0.0.1:`port` (0 = an ephemeral port chosen by the kernel).
  /// @throws std::runtime_error with the port and the system's reason (e.g. the port is in use).
  explicit LoopbackUdpSocket(std::uint16_t port);
  ~LoopbackUdpSocket();
  LoopbackUdpSocket(const LoopbackUdpSocket&) = delete;
  LoopbackUdpSocket& operator=(const LoopbackUdpSocket&) = delete;

  /// The bound port.
  std::uint16_t port() const { return port_; }
  int fd() const { return fd_; }

  /// Sends one packet to 127.0.0.1:`port`. Returns false if the kernel refused it.
  bool SendTo(std::uint16_t port, const BoardPacket& packet) noexcept;
  /// Sends one packet to `peer` (an address a packet came from; always loopback, see Receive).
  bool SendTo(const sockaddr_in& peer, const BoardPacket& packet) noexcept;
  /// Waits until `deadline_ns` (CLOCK_MONOTONIC) for one valid packet from a loopback sender. Returns true
  /// with the packet (and the sender in `peer` if not null); false on timeout. Malformed datagrams and
  /// datagrams from other addresses are dropped. noexcept.
  bool ReceiveUntil(std::int64_t deadline_ns, BoardPacket* packet, sockaddr_in* peer = nullptr) noexcept;

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace mb
