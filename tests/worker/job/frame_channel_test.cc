#include "worker/job/frame_channel.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>
#include <thread>

namespace orcs::worker {
namespace {

using Clock = std::chrono::steady_clock;
using Status = FrameChannel::ReadStatus;

// A connected socket pair, closed at the end of the test.
class FrameChannelTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends_), 0); }
  void TearDown() override {
    for (int fd : ends_) {
      if (fd >= 0) ::close(fd);
    }
  }
  void CloseB() {
    ::close(ends_[1]);
    ends_[1] = -1;
  }
  Clock::time_point Soon() const { return Clock::now() + std::chrono::milliseconds(50); }

  int ends_[2] = {-1, -1};
};

TEST_F(FrameChannelTest, MessagesArriveWholeAndInOrderIncludingEmptyAndBinaryOnes) {
  FrameChannel a(ends_[0]), b(ends_[1]);
  const std::string binary("\0\1\2\xff", 4);
  ASSERT_TRUE(a.Write("first"));
  ASSERT_TRUE(a.Write(""));
  ASSERT_TRUE(a.Write(binary));
  std::string message;
  ASSERT_EQ(b.Read(message, Soon()), Status::kOk);
  EXPECT_EQ(message, "first");
  ASSERT_EQ(b.Read(message, Soon()), Status::kOk);
  EXPECT_EQ(message, "");
  ASSERT_EQ(b.Read(message, Soon()), Status::kOk);
  EXPECT_EQ(message, binary);
}

TEST_F(FrameChannelTest, AMessageLargerThanTheSocketBufferArrivesWhole) {
  FrameChannel a(ends_[0]), b(ends_[1]);
  const std::string big(8 << 20, 'x');  // far beyond a socket buffer: the writer blocks until the reader reads
  std::string message;
  bool written = false;
  std::thread writer([&] { written = a.Write(big); });
  EXPECT_EQ(b.Read(message, Clock::now() + std::chrono::seconds(10)), Status::kOk);
  writer.join();
  EXPECT_TRUE(written);
  EXPECT_EQ(message.size(), big.size());
  EXPECT_EQ(message, big);
}

TEST_F(FrameChannelTest, NothingWithinTheDeadlineTimesOut) {
  FrameChannel b(ends_[1]);
  std::string message;
  EXPECT_EQ(b.Read(message, Soon()), Status::kTimedOut);
  ASSERT_EQ(::send(ends_[0], "\5\0\0\0ab", 6, 0), 6);  // half a message
  EXPECT_EQ(b.Read(message, Soon()), Status::kTimedOut);
}

TEST_F(FrameChannelTest, APeerThatClosesBetweenMessagesIsClosedAndMidMessageIsBroken) {
  FrameChannel a(ends_[0]);
  std::string message;
  {
    FrameChannel b(ends_[1]);
    ASSERT_TRUE(b.Write("last"));
    CloseB();
  }
  ASSERT_EQ(a.Read(message, Soon()), Status::kOk);
  EXPECT_EQ(a.Read(message, Soon()), Status::kClosed);
  EXPECT_FALSE(a.Write("to nobody")) << "no SIGPIPE either: the test would die of it";
}

TEST_F(FrameChannelTest, ATruncatedOrOversizedMessageIsBroken) {
  FrameChannel a(ends_[0]);
  std::string message;
  ASSERT_EQ(::send(ends_[1], "\xff\xff\xff\x7f", 4, 0), 4);  // 2 GiB announced
  EXPECT_EQ(a.Read(message, Soon()), Status::kBroken);
  ASSERT_EQ(::send(ends_[1], "\5\0\0\0ab", 6, 0), 6);
  CloseB();
  EXPECT_EQ(a.Read(message, Soon()), Status::kBroken);
}

}  // namespace
}  // namespace orcs::worker
