// Length-prefixed messages over one end of a connected stream socket: a 4-byte little-endian length, then that
// many bytes. orcs-worker and its sandboxed simulation process (worker/job/simulation_sandbox.h) exchange
// serialised jobs and results this way, one message each way per job.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace orcs::worker {

/// One end of a message channel. Does not own the descriptor.
class FrameChannel {
 public:
  /// How a Read ended.
  enum class ReadStatus {
    kOk,        ///< a whole message was read
    kClosed,    ///< the peer closed its end (or died) before a message began
    kBroken,    ///< the peer closed mid-message, announced an oversized one, or the socket failed
    kTimedOut,  ///< the deadline passed before the message was complete
  };
  /// Messages above this size are refused (as by the broker's sockets): 512 MiB.
  static constexpr std::uint32_t kMaxMessageBytes = 1u << 29;

  /// `fd`: a connected SOCK_STREAM socket (send uses MSG_NOSIGNAL, so a dead peer never raises SIGPIPE).
  explicit FrameChannel(int fd) : fd_(fd) {}

  /// Sends one message; false when the peer is gone or the message is too large.
  bool Write(std::string_view message);
  /// Reads one message into `message`, waiting until `deadline` (time_point::max() = for ever). A signal that
  /// interrupts the wait does not end it.
  ReadStatus Read(std::string& message, std::chrono::steady_clock::time_point deadline);

 private:
  // Fills `size` bytes at `data`; kClosed when the peer closed before the first byte.
  ReadStatus ReadExactly(char* data, std::size_t size, std::chrono::steady_clock::time_point deadline);

  int fd_;
};

}  // namespace orcs::worker
