#include "worker/job/frame_channel.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>

namespace orcs::worker {
namespace {

using Clock = std::chrono::steady_clock;

// Milliseconds poll() may wait before `deadline`, rounded up; -1 = for ever.
int PollTimeout(Clock::time_point deadline) {
  if (deadline == Clock::time_point::max()) return -1;
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<long long>(left, 0, 1 << 30));
}

}  // namespace

bool FrameChannel::Write(std::string_view message) {
  if (message.size() > kMaxMessageBytes) return false;
  const auto size = static_cast<std::uint32_t>(message.size());
  const char header[4] = {static_cast<char>(size & 0xff), static_cast<char>((size >> 8) & 0xff),
                          static_cast<char>((size >> 16) & 0xff), static_cast<char>((size >> 24) & 0xff)};
  for (std::string_view part : {std::string_view(header, sizeof header), message}) {
    while (!part.empty()) {
      const ssize_t sent = ::send(fd_, part.data(), part.size(), MSG_NOSIGNAL);
      if (sent < 0 && errno == EINTR) continue;
      if (sent <= 0) return false;
      part.remove_prefix(static_cast<std::size_t>(sent));
    }
  }
  return true;
}

FrameChannel::ReadStatus FrameChannel::Read(std::string& message, Clock::time_point deadline) {
  unsigned char header[4];
  const ReadStatus status = ReadExactly(reinterpret_cast<char*>(header), sizeof header, deadline);
  if (status != ReadStatus::kOk) return status;
  const std::uint32_t size =
      header[0] | (header[1] << 8) | (header[2] << 16) | (static_cast<std::uint32_t>(header[3]) << 24);
  if (size > kMaxMessageBytes) return ReadStatus::kBroken;
  message.resize(size);
  const ReadStatus body = ReadExactly(message.data(), size, deadline);
  return body == ReadStatus::kClosed ? ReadStatus::kBroken : body;
}

FrameChannel::ReadStatus FrameChannel::ReadExactly(char* data, std::size_t size, Clock::time_point deadline) {
  std::size_t done = 0;
  while (done < size) {
    pollfd item{fd_, POLLIN, 0};
    const int ready = ::poll(&item, 1, PollTimeout(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) return ReadStatus::kBroken;
    if (ready == 0) return ReadStatus::kTimedOut;
    const ssize_t got = ::recv(fd_, data + done, size - done, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && errno != ECONNRESET) return ReadStatus::kBroken;
    if (got <= 0) return done == 0 ? ReadStatus::kClosed : ReadStatus::kBroken;
    done += static_cast<std::size_t>(got);
  }
  return ReadStatus::kOk;
}

}  // namespace orcs::worker
