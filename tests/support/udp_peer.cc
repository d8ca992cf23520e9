#include "tests/support/udp_peer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace orcs::test_support {
namespace {

sockaddr_in Loopback(std::uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(port);
  return address;
}

}  // namespace

UdpPeer::UdpPeer() : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
  const sockaddr_in local = Loopback(0);
  bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local);
}

UdpPeer::~UdpPeer() { Close(); }

void UdpPeer::Close() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

void UdpPeer::SendTo(std::uint16_t port, const Bytes& bytes) {
  const sockaddr_in to = Loopback(port);
  sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
}

std::optional<UdpPeer::Bytes> UdpPeer::Receive(std::chrono::milliseconds timeout, std::uint16_t* from_port) {
  if (fd_ < 0) return std::nullopt;
  pollfd entry{fd_, POLLIN, 0};
  if (poll(&entry, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
  Bytes buffer(4096);
  sockaddr_in from{};
  socklen_t length = sizeof from;
  const ssize_t n = recvfrom(fd_, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &length);
  if (n < 0) return std::nullopt;
  buffer.resize(static_cast<std::size_t>(n));
  if (from_port != nullptr) *from_port = ntohs(from.sin_port);
  return buffer;
}

}  // namespace orcs::test_support
