// The shared DEALER connection on its own, against a raw ROUTER standing in for the broker on 127.0.0.1 (an
// ephemeral port): heartbeats and liveness, reconnecting to a broker that went away and came back, dropped
// messages and the wrong-version text. Every loop is bounded by a deadline and ends as soon as its condition holds.
#include "net/dealer_connection.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "net/envelope_check.h"
#include "orcs/v1/broker.pb.h"
#include "proto/envelope.h"

namespace orcs::net {
namespace {

using Clock = DealerConnection::Clock;
using std::chrono::milliseconds;
using ::testing::HasSubstr;

// A ROUTER standing in for the broker: binds `endpoint` ("tcp://127.0.0.1:*" = any free port).
class FakeBroker {
 public:
  explicit FakeBroker(const std::string& endpoint = "tcp://127.0.0.1:*")
      : context_(1), socket_(context_, zmq::socket_type::router) {
    socket_.set(zmq::sockopt::linger, 0);
    socket_.bind(endpoint);
    endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
  }
  const std::string& endpoint() const { return endpoint_; }

  struct Message {
    std::string peer;     ///< the DEALER's routing id
    std::string payload;  ///< the message's one frame
  };
  // The next message, or nullopt after `limit`.
  std::optional<Message> Receive(milliseconds limit = milliseconds(5000)) {
    zmq::pollitem_t item{socket_.handle(), 0, ZMQ_POLLIN, 0};
    if (zmq::poll(&item, 1, limit) == 0) return std::nullopt;
    zmq::message_t peer;
    zmq::message_t payload;
    (void)socket_.recv(peer);
    (void)socket_.recv(payload);
    return Message{peer.to_string(), payload.to_string()};
  }
  void Send(const std::string& peer, const std::vector<std::string>& frames) {
    socket_.send(zmq::buffer(peer), zmq::send_flags::sndmore);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      socket_.send(zmq::buffer(frames[i]), i + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
    }
  }

 private:
  zmq::context_t context_;
  zmq::socket_t socket_;
  std::string endpoint_;
};

std::string Heartbeat() {
  v1::WorkerToBroker heartbeat;
  heartbeat.set_protocol_version(proto::kProtocolVersion);
  heartbeat.mutable_heartbeat();
  return heartbeat.SerializeAsString();
}

std::string BrokerHeartbeat(std::uint32_t version = proto::kProtocolVersion) {
  v1::BrokerToWorker heartbeat;
  heartbeat.set_protocol_version(version);
  heartbeat.mutable_heartbeat();
  return heartbeat.SerializeAsString();
}

// A connection with short intervals, logging into `log`.
DealerConnectionOptions Options(const std::string& endpoint, std::vector<std::string>& log,
                                milliseconds interval = milliseconds(50), int liveness = 4) {
  DealerConnectionOptions options;
  options.endpoint = endpoint;
  options.role = "worker";
  options.owner = "DealerTest";
  options.heartbeat_interval = interval;
  options.liveness = liveness;
  options.heartbeat = Heartbeat();
  options.log = [&log](const std::string& line) { log.push_back(line); };
  return options;
}

// Opens `dealer` and says hello: the broker's routing id for it, or "" when the broker heard nothing.
std::string Introduce(DealerConnection& dealer, FakeBroker& broker) {
  dealer.Open();
  dealer.Send("hello");
  const std::optional<FakeBroker::Message> hello = broker.Receive();
  return hello ? hello->peer : "";
}

int CountContaining(const std::vector<std::string>& log, const std::string& part) {
  int count = 0;
  for (const std::string& line : log) count += line.find(part) != std::string::npos ? 1 : 0;
  return count;
}

// Reads every waiting frame; marks the broker heard for each valid one. Returns how many were valid.
int ReadAll(DealerConnection& dealer) {
  int valid = 0;
  zmq::message_t frame;
  v1::BrokerToWorker in;
  while (dealer.Receive(frame) == DealerConnection::Received::kFrame) {
    if (!CheckEnvelope(frame, in).empty()) continue;
    dealer.MarkHeard();
    ++valid;
  }
  return valid;
}

// The I/O loop of a side, cut down: heartbeats until the broker counts as lost or `limit` passes. Returns whether
// the broker was lost.
bool HeartbeatUntilLost(DealerConnection& dealer, milliseconds limit) {
  const Clock::time_point give_up = Clock::now() + limit;
  while (Clock::now() < give_up) {
    const DealerConnection::PollEvents events =
        dealer.Poll(std::min({dealer.next_heartbeat(), dealer.liveness_deadline(), give_up}));
    if (events.readable) ReadAll(dealer);
    const Clock::time_point now = Clock::now();
    dealer.HeartbeatIfDue(now);
    if (now >= dealer.liveness_deadline()) return true;
  }
  return false;
}

TEST(DealerConnectionTest, RefusesAnEndpointZeroMqCannotParse) {
  std::vector<std::string> log;
  try {
    DealerConnection dealer(Options("nonsense", log));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("DealerTest: cannot connect to 'nonsense': "));
  }
}

TEST(DealerConnectionTest, HeartbeatsEveryIntervalAndStaysAliveWhileTheBrokerAnswers) {
  FakeBroker broker;
  std::vector<std::string> log;
  // A liveness period of 10 intervals (0.5 s): room for a loaded machine between an answer and the next check.
  DealerConnection dealer(Options(broker.endpoint(), log, milliseconds(50), 10));
  dealer.Open();
  dealer.ScheduleHeartbeat(Clock::now());
  int heartbeats = 0;
  const Clock::time_point give_up = Clock::now() + milliseconds(10000);
  while (heartbeats < 8 && Clock::now() < give_up) {
    const DealerConnection::PollEvents events = dealer.Poll(dealer.next_heartbeat());
    if (events.readable) ReadAll(dealer);
    ASSERT_LT(Clock::now(), dealer.liveness_deadline()) << "the answering broker counted as lost";
    if (!dealer.HeartbeatIfDue(Clock::now())) continue;
    const std::optional<FakeBroker::Message> got = broker.Receive();
    ASSERT_TRUE(got);
    EXPECT_EQ(got->payload, Heartbeat());
    broker.Send(got->peer, {BrokerHeartbeat()});  // any valid message is proof of life
    ++heartbeats;
  }
  EXPECT_EQ(heartbeats, 8);
  EXPECT_TRUE(log.empty());
}

TEST(DealerConnectionTest, ASilentBrokerIsLostAfterTheLivenessPeriodNotBefore) {
  FakeBroker broker;  // receives the heartbeats, never answers
  std::vector<std::string> log;
  DealerConnection dealer(Options(broker.endpoint(), log, milliseconds(20), 3));
  dealer.Open();
  const Clock::time_point opened = Clock::now();
  dealer.ScheduleHeartbeat(opened);
  ASSERT_TRUE(HeartbeatUntilLost(dealer, milliseconds(10000)));
  EXPECT_GE(Clock::now() - opened, dealer.liveness_period());
  EXPECT_EQ(dealer.liveness_period(), milliseconds(60));
  int heartbeats = 0;
  while (broker.Receive(milliseconds(200))) ++heartbeats;
  EXPECT_GE(heartbeats, 1);  // they kept leaving while the broker was silent

  // Hearing the broker moves the deadline one liveness period past that moment.
  dealer.MarkHeard();
  EXPECT_EQ(dealer.liveness_deadline(), dealer.last_heard() + dealer.liveness_period());
}

// A broker slower than this side (its heartbeat said so) is waited for at its pace, up to a minute's.
TEST(DealerConnectionTest, TheLivenessFollowsTheSlowerSideUpToAMinute) {
  FakeBroker broker;
  std::vector<std::string> log;
  DealerConnection dealer(Options(broker.endpoint(), log, milliseconds(20), 3));
  dealer.NotePeerInterval(milliseconds(100));
  EXPECT_EQ(dealer.liveness_period(), milliseconds(300));
  dealer.NotePeerInterval(milliseconds(5));  // faster than this side: its own pace counts
  EXPECT_EQ(dealer.liveness_period(), milliseconds(60));
  dealer.NotePeerInterval(std::chrono::hours(1));
  EXPECT_EQ(dealer.liveness_period(), std::chrono::minutes(3));
}

TEST(DealerConnectionTest, ConnectsAgainToABrokerThatWentAwayAndCameBack) {
  std::vector<std::string> log;
  std::optional<FakeBroker> broker(std::in_place);
  const std::string endpoint = broker->endpoint();  // the port the returning broker binds again
  DealerConnection dealer(Options(endpoint, log));
  dealer.Open();
  dealer.ScheduleHeartbeat(Clock::now());
  dealer.Send("hello");
  const std::optional<FakeBroker::Message> first = broker->Receive();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->payload, "hello");

  broker.reset();  // the broker goes away
  ASSERT_TRUE(HeartbeatUntilLost(dealer, milliseconds(10000)));
  dealer.ReportSilence("no answer from the broker; connecting again");
  dealer.ReportSilence("no answer from the broker; connecting again");  // one line for one outage
  dealer.Reopen();
  dealer.Send("hello again");  // queued until the broker is back

  broker.emplace(endpoint);
  const std::optional<FakeBroker::Message> again = broker->Receive();
  ASSERT_TRUE(again);
  EXPECT_EQ(again->payload, "hello again");
  EXPECT_NE(again->peer, first->peer);  // a new connection, as the broker sees it
  broker->Send(again->peer, {BrokerHeartbeat()});
  int heard = 0;
  const Clock::time_point give_up = Clock::now() + milliseconds(5000);
  while (heard == 0 && Clock::now() < give_up) {
    if (dealer.Poll(give_up).readable) heard += ReadAll(dealer);
  }
  EXPECT_EQ(heard, 1);
  EXPECT_EQ(CountContaining(log, "connecting again"), 1);
  EXPECT_EQ(CountContaining(log, "the broker at " + endpoint + " answers again"), 1);
}

TEST(DealerConnectionTest, DescribesAWrongVersionWithTheVersionFound) {
  EXPECT_EQ(DescribeRejection(proto::EnvelopeCheck::kWrongVersion, 7), "wrong protocol version 7 (expected " + std::to_string(proto::kProtocolVersion) + ")");
  EXPECT_EQ(DescribeRejection(proto::EnvelopeCheck::kOk, 1), "");
  EXPECT_EQ(DescribeRejection(proto::EnvelopeCheck::kNoBody, 1), "message without a body");

  const zmq::message_t wrong(BrokerHeartbeat(7));
  v1::BrokerToClient client_side;
  EXPECT_EQ(CheckEnvelope(wrong, client_side), "wrong protocol version 7 (expected " + std::to_string(proto::kProtocolVersion) + ")");
  v1::BrokerToWorker worker_side;
  EXPECT_EQ(CheckEnvelope(wrong, worker_side), "wrong protocol version 7 (expected " + std::to_string(proto::kProtocolVersion) + ")");
  EXPECT_EQ(CheckEnvelope(zmq::message_t(BrokerHeartbeat(0)), worker_side), "wrong protocol version 0 (expected " + std::to_string(proto::kProtocolVersion) + ")");
  EXPECT_EQ(CheckEnvelope(zmq::message_t(std::string("\xff\xff\xff")), worker_side),
            "not a protocol message (failed to parse)");
  EXPECT_EQ(CheckEnvelope(zmq::message_t(BrokerHeartbeat()), worker_side), "");
}

TEST(DealerConnectionTest, DropsMultipartAndBadMessagesWithOneLogLinePerConnection) {
  FakeBroker broker;
  std::vector<std::string> log;
  DealerConnection dealer(Options(broker.endpoint(), log));
  const std::string peer = Introduce(dealer, broker);
  ASSERT_FALSE(peer.empty());
  broker.Send(peer, {"one", "two"});
  broker.Send(peer, {BrokerHeartbeat(7)});
  broker.Send(peer, {BrokerHeartbeat()});

  std::vector<DealerConnection::Received> seen;
  zmq::message_t frame;
  const Clock::time_point give_up = Clock::now() + milliseconds(5000);
  while (seen.size() < 3 && Clock::now() < give_up) {
    if (!dealer.Poll(give_up).readable) continue;
    for (DealerConnection::Received got; (got = dealer.Receive(frame)) != DealerConnection::Received::kNone;) {
      seen.push_back(got);
      v1::BrokerToWorker in;
      const std::string why =
          got == DealerConnection::Received::kMultipart ? "a message of several frames" : CheckEnvelope(frame, in);
      if (!why.empty()) dealer.ReportDropped(why);
    }
  }
  EXPECT_THAT(seen, ::testing::ElementsAre(DealerConnection::Received::kMultipart, DealerConnection::Received::kFrame,
                                           DealerConnection::Received::kFrame));
  ASSERT_EQ(log.size(), 1u);
  EXPECT_THAT(log[0], HasSubstr("dropped a message from the broker at " + broker.endpoint() +
                                ": a message of several frames"));
  dealer.Reopen();  // a new connection logs its first bad message again
  dealer.ReportDropped(DescribeRejection(proto::EnvelopeCheck::kWrongVersion, 7));
  ASSERT_EQ(log.size(), 2u);
  EXPECT_THAT(log[1], HasSubstr(": wrong protocol version 7 (expected " + std::to_string(proto::kProtocolVersion) +
                                    ") (further bad messages"));
}

TEST(DealerConnectionTest, ReceiveAllReadsUntilItsHandlerStopsAndNamesAMultipartMessage) {
  FakeBroker broker;
  std::vector<std::string> log;
  DealerConnection dealer(Options(broker.endpoint(), log));
  const std::string peer = Introduce(dealer, broker);
  ASSERT_FALSE(peer.empty());
  for (const char* frame : {"a", "stop", "c"}) {
    broker.Send(peer, {frame});
    if (std::string(frame) == "a") broker.Send(peer, {"one", "two"});
  }

  std::vector<std::string> frames;
  std::vector<std::string> dropped;
  const auto on_frame = [&frames](const zmq::message_t& frame) {
    frames.push_back(frame.to_string());
    return frames.back() != "stop";  // the handler replaced its socket: reading stops here
  };
  const auto on_dropped = [&dropped](const std::string& why) { dropped.push_back(why); };
  const Clock::time_point give_up = Clock::now() + milliseconds(5000);
  while (frames.size() < 2 && Clock::now() < give_up) {
    if (dealer.Poll(give_up).readable) dealer.ReceiveAll(on_frame, on_dropped);
  }
  EXPECT_THAT(frames, ::testing::ElementsAre("a", "stop"));
  EXPECT_THAT(dropped, ::testing::ElementsAre("a message of several frames"));
  while (frames.size() < 3 && Clock::now() < give_up) {  // "c" waits for the next read
    if (dealer.Poll(give_up).readable) dealer.ReceiveAll(on_frame, on_dropped);
  }
  EXPECT_THAT(frames, ::testing::ElementsAre("a", "stop", "c"));
}

TEST(DealerConnectionTest, WakeEndsAPollAtOnce) {
  FakeBroker broker;
  std::vector<std::string> log;
  DealerConnection dealer(Options(broker.endpoint(), log));
  dealer.Open();
  const Clock::time_point start = Clock::now();
  std::thread waker([&dealer] { dealer.Wake(); });
  const DealerConnection::PollEvents events = dealer.Poll(start + milliseconds(10000));
  waker.join();
  EXPECT_FALSE(events.readable);
  EXPECT_LT(Clock::now() - start, milliseconds(5000));
}

}  // namespace
}  // namespace orcs::net
