// A UDP socket on 127.0.0.1 for tests that talk to a real server over loopback (orcs-osp, the ODCP robot side).
// Plain POSIX sockets, independent of orcs's own networking code, so that a protocol test checks the server
// against the spec and not against the code it shares.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

namespace orcs::test_support {

class UdpPeer {
 public:
  using Bytes = std::vector<std::uint8_t>;

  /// Binds an ephemeral port on 127.0.0.1.
  UdpPeer();
  ~UdpPeer();
  UdpPeer(const UdpPeer&) = delete;
  UdpPeer& operator=(const UdpPeer&) = delete;

  /// One datagram to 127.0.0.1:`port`.
  void SendTo(std::uint16_t port, const Bytes& bytes);
  /// The next datagram within `timeout` (at most 4096 bytes), and in `from_port` the port it came from; nullopt
  /// when none came (or the socket is closed).
  std::optional<Bytes> Receive(std::chrono::milliseconds timeout = std::chrono::milliseconds(5000),
                               std::uint16_t* from_port = nullptr);
  /// Closes the socket now (a client that goes away without a word).
  void Close();

 private:
  int fd_ = -1;
};

}  // namespace orcs::test_support
