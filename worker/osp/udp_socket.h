// A non-blocking IPv4 UDP socket, closed with its owner: what the OSP and ODCP servers (and their tests'
// clients) send and receive datagrams through.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orcs::osp {

/// An IPv4 address and port.
struct Endpoint {
  std::uint32_t address = 0;  ///< host byte order, e.g. 0x7f000001 for 127.0.0.1
  std::uint16_t port = 0;     ///< host byte order
  bool operator==(const Endpoint&) const = default;
  std::string ToString() const;  ///< "127.0.0.1:45454"
};

/// One datagram received.
struct Datagram {
  std::vector<std::uint8_t> bytes;  ///< its payload (at most the receive buffer; longer ones are cut)
  Endpoint from;                    ///< the sender
  bool truncated = false;           ///< longer than the buffer: the tail was dropped
};

class UdpSocket {
 public:
  /// Binds to `address` ("127.0.0.1", "0.0.0.0" or "*") and `port` (0 = ephemeral). Throws std::runtime_error
  /// naming the address when it cannot.
  UdpSocket(const std::string& address, std::uint16_t port);
  ~UdpSocket();
  UdpSocket(UdpSocket&& other) noexcept;
  UdpSocket& operator=(UdpSocket&& other) noexcept;
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  int fd() const { return fd_; }
  /// The bound address and port (the actual port when 0 was asked for).
  Endpoint local() const;

  /// From now on, Send() goes to `peer` and only its datagrams arrive.
  void Connect(const Endpoint& peer);
  /// Sends to the connected peer; false when the kernel refused (e.g. the peer's port is closed).
  bool Send(std::span<const std::uint8_t> bytes);
  /// Sends to `peer`; false when the kernel refused.
  bool SendTo(std::span<const std::uint8_t> bytes, const Endpoint& peer);
  /// The next waiting datagram, nullopt when none is waiting (non-blocking).
  std::optional<Datagram> Receive(std::size_t max_bytes = 2048);
  /// The socket's pending error (errno value, 0 for none), cleared by reading it: on a connected socket,
  /// ECONNREFUSED says an ICMP "port unreachable" came back for something sent: the peer's socket is closed.
  int TakeError();
  /// Waits up to `timeout_ms` for a datagram to be waiting; true when one is.
  bool WaitReadable(int timeout_ms) const;

 private:
  int fd_ = -1;
};

/// Parses "127.0.0.1" (or "localhost", "*" = any) into a host-order address; throws std::runtime_error.
std::uint32_t ParseIPv4(const std::string& address);

}  // namespace orcs::osp
