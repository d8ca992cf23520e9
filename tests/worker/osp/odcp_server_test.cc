// The ODCP 1.0 server over a real UDP socket on 127.0.0.1 (its replies, the word ↔ angle and torque mapping,
// every kind of bad datagram), the port numbering, and the KeyFrameSniffer's rows under a fake clock.
#include "worker/osp/odcp_server.h"

#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "model/control/keyframe_record.h"
#include "worker/osp/keyframe_sniffer.h"

namespace orcs::osp {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Motors kept in memory: what the server sets, it reads back.
class FakeMotors : public OdcpMotors {
 public:
  explicit FakeMotors(int count) : angles(static_cast<std::size_t>(count), 0.0), torques(angles.size(), 0.5) {}
  int motor_count() const override { return static_cast<int>(angles.size()); }
  double angle(int m) const override { return angles[static_cast<std::size_t>(m)]; }
  double torque(int m) const override { return torques[static_cast<std::size_t>(m)]; }
  void Set(std::span<const double> a, std::span<const double> t) override {
    angles.assign(a.begin(), a.end());
    torques.assign(t.begin(), t.end());
    ++sets;
  }
  void OnConnect() override { ++connects; }
  void OnDisconnect() override { ++disconnects; }
  std::vector<double> angles;   // goal angles, degrees
  std::vector<double> torques;  // raw torques, 0…1
  int sets = 0;                 // set-motors commands applied
  int connects = 0;             // connects answered
  int disconnects = 0;          // disconnects answered
};

Bytes Words(std::uint8_t code, const std::vector<std::int32_t>& words) {
  Bytes bytes{code};
  for (std::int32_t w : words) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(w) >> (8 * i)));
  }
  return bytes;
}

std::vector<std::int32_t> IntsAfterCode(const Bytes& bytes) {
  std::vector<std::int32_t> ints;
  for (std::size_t at = 1; at + 4 <= bytes.size(); at += 4) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | bytes[at + static_cast<std::size_t>(i)];
    ints.push_back(static_cast<std::int32_t>(v));
  }
  return ints;
}

class OdcpServerTest : public ::testing::Test {
 protected:
  OdcpServerTest() : client_("127.0.0.1", 0) {
    OdcpServerOptions options;
    options.port = 0;
    options.log = [this](std::string_view line) { log_.emplace_back(line); };
    server_ = std::make_unique<OdcpServer>(motors_, options);
  }
  // Sends `bytes` to the server and lets it answer everything waiting.
  void Send(const Bytes& bytes) {
    client_.SendTo(bytes, server_->endpoint());
    pollfd entry{server_->fd(), POLLIN, 0};
    ASSERT_EQ(poll(&entry, 1, 5000), 1) << "the datagram arrives";
    server_->OnReadable();
  }
  std::optional<Bytes> Reply(int timeout_ms = 2000) {
    if (!client_.WaitReadable(timeout_ms)) return std::nullopt;
    std::optional<Datagram> datagram = client_.Receive();
    if (!datagram) return std::nullopt;
    EXPECT_EQ(datagram->from, server_->endpoint());
    return datagram->bytes;
  }

  FakeMotors motors_{3};
  UdpSocket client_;
  std::vector<std::string> log_;
  std::unique_ptr<OdcpServer> server_;
};

TEST(OdcpWordsTest, MapWordsToAnglesAndTorquesAsTheSpecSays) {
  // n = −1 + 2w/1023; angle 150·n degrees; torque (n+1)/2 of the maximum.
  EXPECT_DOUBLE_EQ(OdcpAngleOfWord(0), -150.0);
  EXPECT_DOUBLE_EQ(OdcpAngleOfWord(1023), 150.0);
  EXPECT_DOUBLE_EQ(OdcpAngleOfWord(767), 150.0 * (-1.0 + 2.0 * 767 / 1023));
  EXPECT_DOUBLE_EQ(OdcpTorqueOfWord(0), 0.0);
  EXPECT_DOUBLE_EQ(OdcpTorqueOfWord(1023), 1.0);
  EXPECT_DOUBLE_EQ(OdcpTorqueOfWord(600), 600.0 / 1023);
  // Out-of-range words count as the nearest end.
  EXPECT_DOUBLE_EQ(OdcpAngleOfWord(-7), -150.0);
  EXPECT_DOUBLE_EQ(OdcpTorqueOfWord(1 << 30), 1.0);
}

TEST(OdcpWordsTest, EveryWordRoundTripsAndRawValuesMapToTheNearestWord) {
  for (std::int32_t w = 0; w <= 1023; ++w) {
    ASSERT_EQ(OdcpWordOfAngle(OdcpAngleOfWord(w)), w);
    ASSERT_EQ(OdcpWordOfTorque(OdcpTorqueOfWord(w)), w);
  }
  EXPECT_EQ(OdcpWordOfAngle(0.0), 512);  // 511.5 rounds up
  EXPECT_EQ(OdcpWordOfAngle(400.0), 1023);
  EXPECT_EQ(OdcpWordOfAngle(-400.0), 0);
  EXPECT_EQ(OdcpWordOfTorque(-0.5), 0) << "a negative torque is no torque";
  EXPECT_EQ(OdcpWordOfTorque(0.586810005), 600);
  EXPECT_EQ(OdcpWordOfTorque(std::nan("")), 0);
}

TEST(OdcpPortsTest, CountFromTheBaseSkippingTheOspPort) {
  EXPECT_EQ(OdcpPorts(45453, 3, 45454), (std::vector<std::uint16_t>{45453, 45455, 45456}));
  EXPECT_EQ(OdcpPorts(45400, 2, 45454), (std::vector<std::uint16_t>{45400, 45401}));
  EXPECT_EQ(OdcpPorts(0, 2, 45454), (std::vector<std::uint16_t>{0, 0})) << "ephemeral";
  EXPECT_THROW(OdcpPorts(65535, 2, 45454), std::runtime_error);
}

TEST_F(OdcpServerTest, ConnectAndDisconnectAreAnsweredWithoutATerminator) {
  Send({5});
  EXPECT_EQ(Reply(), (Bytes{6, 15, 0, 0, 0, 1, 0, 0, 0}));
  Send({7});
  EXPECT_EQ(Reply(), (Bytes{8}));
  EXPECT_EQ(motors_.connects, 1);
  EXPECT_EQ(motors_.disconnects, 1);
}

TEST_F(OdcpServerTest, SetMotorsTakesAnglesThenTorquesAndGetMotorsGivesTheWordsBack) {
  Send(Words(100, {0, 512, 1023, 1023, 0, 600}));
  EXPECT_FALSE(Reply(200).has_value()) << "set-motors has no reply";
  EXPECT_EQ(motors_.sets, 1);
  EXPECT_DOUBLE_EQ(motors_.angles[0], -150.0);
  EXPECT_NEAR(motors_.angles[1], 150.0 / 1023, 1e-12);
  EXPECT_DOUBLE_EQ(motors_.angles[2], 150.0);
  EXPECT_EQ(motors_.torques, (std::vector<double>{1.0, 0.0, 600.0 / 1023}));
  Send({150});
  const std::optional<Bytes> reply = Reply();
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->front(), 151);
  EXPECT_EQ(reply->size(), 1u + 6 * 4);
  EXPECT_EQ(IntsAfterCode(*reply), (std::vector<std::int32_t>{0, 512, 1023, 1023, 0, 600}));
}

TEST_F(OdcpServerTest, BadDatagramsAreIgnoredOrClampedAndTheServerGoesOn) {
  const std::vector<Bytes> ignored = {
      {},                              // empty
      {100, 1, 2},                     // set-motors cut short
      Words(100, {1, 2, 3, 4, 5}),     // one word too few
      Words(100, {1, 2, 3, 4, 5, 6, 7}),  // one too many
      Bytes(3000, 100),                // oversized
      {42, 1, 2, 3},                   // unknown command
  };
  for (const Bytes& bytes : ignored) Send(bytes);
  EXPECT_FALSE(Reply(200).has_value());
  EXPECT_EQ(motors_.sets, 0) << "nothing applied";
  EXPECT_EQ(server_->stats().datagrams_ignored, ignored.size());
  EXPECT_EQ(log_.size(), 1u) << "one line, not a flood";
  constexpr std::int32_t kLowest = std::numeric_limits<std::int32_t>::min();
  constexpr std::int32_t kHighest = std::numeric_limits<std::int32_t>::max();
  Send(Words(100, {-5, 2000, kLowest, 512, 512, kHighest}));
  EXPECT_EQ(server_->stats().words_clamped, 4u);
  Send({150, 99, 99});  // get-motors with trailing bytes: answered
  const std::optional<Bytes> reply = Reply();
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(IntsAfterCode(*reply), (std::vector<std::int32_t>{0, 1023, 0, 512, 512, 1023}));
}

TEST(KeyframeSnifferTest, RecordsEachCommandAtItsTimeSinceTheFirstAndFinishesOnDisconnect) {
  using Clock = KeyframeSniffer::Clock;
  Clock::time_point now = Clock::time_point() + std::chrono::seconds(100);
  KeyframeSniffer sniffer(2, [&now] { return now; });
  EXPECT_EQ(sniffer.angle(1), 0.0);
  EXPECT_EQ(sniffer.torque(1), 0.586810005) << "the A-Series defaults before the first command";
  sniffer.OnDisconnect();
  EXPECT_FALSE(sniffer.finished()) << "a disconnect before any command is an editor probing";
  const std::vector<double> angles1{10.0, -20.0};
  const std::vector<double> torques1{1.0, 0.5};
  sniffer.Set(angles1, torques1);
  now += std::chrono::microseconds(250125);
  const std::vector<double> angles2{30.0, 40.0};
  const std::vector<double> torques2{0.0, 0.25};
  sniffer.Set(angles2, torques2);
  EXPECT_EQ(sniffer.angle(0), 30.0);
  EXPECT_EQ(sniffer.torque(1), 0.25);
  sniffer.OnDisconnect();
  EXPECT_TRUE(sniffer.finished());
  const control::KeyframeRecord& record = sniffer.record();
  ASSERT_EQ(record.frames.size(), 2u);
  EXPECT_EQ(record.frames[0].time_ms, 0.0);
  EXPECT_EQ(record.frames[1].time_ms, 250.125);
  EXPECT_EQ(record.frames[0].inputs, (std::vector<double>{10.0, 1.0, -20.0, 0.5})) << "input order";
  // The text replays: it parses back to the same rows.
  const control::KeyframeRecord parsed =
      control::ParseKeyframeRecord(control::FormatKeyframeRecord(record, {"test"}), "sniffed.csv", 2);
  ASSERT_EQ(parsed.frames.size(), 2u);
  EXPECT_EQ(parsed.frames[1].time_ms, 250.125);
  EXPECT_EQ(parsed.frames[1].inputs, (std::vector<double>{30.0, 0.0, 40.0, 0.25}));
}

}  // namespace
}  // namespace orcs::osp
