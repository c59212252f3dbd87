#include "hw/udp_socket.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "hw/realtime.h"

namespace mb {

namespace {
sockaddr_in LoopbackAddress(std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}
}  // namespace

LoopbackUdpSocket::LoopbackUdpSocket(std::uint16_t port) {
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) throw std::runtime_error(fmt::format("UDP socket: {}", std::strerror(errno)));
  sockaddr_in a = LoopbackAddress(port);
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int error = errno;
    close(fd_);
    throw std::runtime_error(fmt::format("cannot bind UDP 127.0.0.1:{}: {} (choose another --port, or 0 for a "
                                         "free one)",
                                         port, std::strerror(error)));
  }
  socklen_t length = sizeof a;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length);
  port_ = ntohs(a.sin_port);
}

LoopbackUdpSocket::~LoopbackUdpSocket() {
  if (fd_ >= 0) close(fd_);
}

bool LoopbackUdpSocket::SendTo(std::uint16_t port, const BoardPacket& packet) noexcept {
  return SendTo(LoopbackAddress(port), packet);
}

bool LoopbackUdpSocket::SendTo(const sockaddr_in& peer, const BoardPacket& packet) noexcept {
  if (peer.sin_addr.s_addr != htonl(INADDR_LOOPBACK)) return false;  // loopback only, by construction
  PacketBytes bytes;
  EncodePacket(packet, &bytes);
  const ssize_t sent = sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&peer),
                              sizeof peer);
  return sent == static_cast<ssize_t>(bytes.size());
}

bool LoopbackUdpSocket::ReceiveUntil(std::int64_t deadline_ns, BoardPacket* packet, sockaddr_in* peer) noexcept {
  PacketBytes bytes;
  for (;;) {
    sockaddr_in from{};
    socklen_t length = sizeof from;
    const ssize_t got =
        recvfrom(fd_, bytes.data(), bytes.size(), MSG_TRUNC, reinterpret_cast<sockaddr*>(&from), &length);
    if (got >= 0) {
      if (from.sin_addr.s_addr != htonl(INADDR_LOOPBACK)) continue;
      if (!DecodePacket(bytes.data(), static_cast<std::size_t>(got), packet)) continue;
      if (peer != nullptr) *peer = from;
      return true;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) return false;
    const std::int64_t remaining = deadline_ns - MonotonicNanoseconds();
    if (remaining <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    timespec timeout{static_cast<time_t>(remaining / 1'000'000'000), static_cast<long>(remaining % 1'000'000'000)};
    if (ppoll(&p, 1, &timeout, nullptr) == 0) return false;
  }
}

}  // namespace mb
