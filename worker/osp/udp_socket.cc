#include "worker/osp/udp_socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "model/core/text.h"

namespace orcs::osp {
namespace {

sockaddr_in ToSockaddr(const Endpoint& endpoint) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(endpoint.address);
  address.sin_port = htons(endpoint.port);
  return address;
}

Endpoint FromSockaddr(const sockaddr_in& address) {
  return Endpoint{ntohl(address.sin_addr.s_addr), ntohs(address.sin_port)};
}

}  // namespace

std::string Endpoint::ToString() const {
  return std::to_string(address >> 24) + "." + std::to_string((address >> 16) & 255) + "." +
         std::to_string((address >> 8) & 255) + "." + std::to_string(address & 255) + ":" + std::to_string(port);
}

std::uint32_t ParseIPv4(const std::string& address) {
  if (address == "*" || address == "0.0.0.0") return INADDR_ANY;
  if (address == "localhost") return INADDR_LOOPBACK;
  in_addr parsed{};
  if (inet_pton(AF_INET, address.c_str(), &parsed) != 1) {
    throw std::runtime_error(text::Quote(address) + " is not an IPv4 address");
  }
  return ntohl(parsed.s_addr);
}

UdpSocket::UdpSocket(const std::string& address, std::uint16_t port) {
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("cannot open a UDP socket: ") + std::strerror(errno));
  const sockaddr_in bound = ToSockaddr({ParseIPv4(address), port});
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&bound), sizeof bound) != 0) {
    const std::string why = std::strerror(errno);
    close(fd_);
    fd_ = -1;
    throw std::runtime_error("cannot bind UDP " + address + ":" + std::to_string(port) + ": " + why);
  }
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) close(fd_);
}

UdpSocket::UdpSocket(UdpSocket&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

Endpoint UdpSocket::local() const {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length);
  return FromSockaddr(address);
}

void UdpSocket::Connect(const Endpoint& peer) {
  const sockaddr_in address = ToSockaddr(peer);
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    throw std::runtime_error("cannot connect a UDP socket to " + peer.ToString() + ": " + std::strerror(errno));
  }
}

bool UdpSocket::Send(std::span<const std::uint8_t> bytes) {
  return send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
}

bool UdpSocket::SendTo(std::span<const std::uint8_t> bytes, const Endpoint& peer) {
  const sockaddr_in address = ToSockaddr(peer);
  return sendto(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&address),
                sizeof address) == static_cast<ssize_t>(bytes.size());
}

std::optional<Datagram> UdpSocket::Receive(std::size_t max_bytes) {
  Datagram datagram;
  datagram.bytes.resize(max_bytes);
  sockaddr_in from{};
  socklen_t length = sizeof from;
  const ssize_t received = recvfrom(fd_, datagram.bytes.data(), max_bytes, MSG_TRUNC,
                                    reinterpret_cast<sockaddr*>(&from), &length);
  if (received < 0) return std::nullopt;  // EAGAIN, or an ICMP error from an earlier send: nothing to read
  datagram.truncated = static_cast<std::size_t>(received) > max_bytes;
  datagram.bytes.resize(std::min(static_cast<std::size_t>(received), max_bytes));
  datagram.from = FromSockaddr(from);
  return datagram;
}

int UdpSocket::TakeError() {
  int error = 0;
  socklen_t length = sizeof error;
  if (getsockopt(fd_, SOL_SOCKET, SO_ERROR, &error, &length) != 0) return errno;
  return error;
}

bool UdpSocket::WaitReadable(int timeout_ms) const {
  pollfd entry{fd_, POLLIN, 0};
  return poll(&entry, 1, timeout_ms) > 0 && (entry.revents & POLLIN) != 0;
}

}  // namespace orcs::osp
