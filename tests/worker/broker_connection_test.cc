// WorkerConnection against a fake broker (a raw ROUTER socket the test drives by hand) and against the real one.
#include "worker/broker_connection.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "proto/envelope.h"
#include "tests/broker/test_peers.h"

namespace orcs::test_support {
namespace {

using std::chrono::milliseconds;
using ::testing::HasSubstr;
using worker::WorkerConnection;

// A ROUTER on an ephemeral port standing in for the broker.
class FakeBroker {
 public:
  FakeBroker() : context_(1), socket_(context_, zmq::socket_type::router) {
    socket_.set(zmq::sockopt::linger, 0);
    socket_.bind("tcp://127.0.0.1:*");
    endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
  }
  const std::string& endpoint() const { return endpoint_; }

  struct Received {
    std::string peer;
    v1::WorkerToBroker message;
  };
  // The next message that is not a heartbeat; nullopt after `limit`.
  std::optional<Received> Receive(milliseconds limit = milliseconds(5000)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      zmq::pollitem_t item{socket_.handle(), 0, ZMQ_POLLIN, 0};
      if (zmq::poll(&item, 1, milliseconds(20)) == 0) continue;
      zmq::message_t peer;
      zmq::message_t payload;
      (void)socket_.recv(peer);
      (void)socket_.recv(payload);
      Received received{peer.to_string(), {}};
      if (!received.message.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) continue;
      if (received.message.has_heartbeat()) continue;
      return received;
    }
    return std::nullopt;
  }
  void SendFrames(const std::string& peer, const std::vector<std::string>& frames) {
    socket_.send(zmq::buffer(peer), zmq::send_flags::sndmore);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      socket_.send(zmq::buffer(frames[i]), i + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
    }
  }
  void Send(const std::string& peer, const v1::BrokerToWorker& message) {
    SendFrames(peer, {message.SerializeAsString()});
  }
  void SendJob(const std::string& peer, const v1::Job& job) {
    v1::BrokerToWorker message;
    message.set_protocol_version(proto::kProtocolVersion);
    *message.mutable_job() = job;
    Send(peer, message);
  }

 private:
  zmq::context_t context_;
  zmq::socket_t socket_;
  std::string endpoint_;
};

TEST(WorkerConnection, AnnouncesItselfWithItsCreditAndHeartbeats) {
  FakeBroker broker;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "named", 3));
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready && ready->message.has_ready());
  EXPECT_EQ(ready->message.protocol_version(), proto::kProtocolVersion);
  EXPECT_EQ(ready->message.ready().worker_id(), "named");
  EXPECT_EQ(ready->message.ready().credit(), 3u);
  EXPECT_EQ(connection.worker_id(), "named");
  EXPECT_EQ(connection.stats().connections, 1u);
}

TEST(WorkerConnection, DefaultNameIsHostAndProcess) {
  FakeBroker broker;
  worker::WorkerConnectionOptions options = TestWorkerOptions(broker.endpoint(), "", 1);
  WorkerConnection connection(options);
  EXPECT_THAT(connection.worker_id(), ::testing::EndsWith("-" + std::to_string(::getpid())));
}

TEST(WorkerConnection, HandsOutJobsInOrderAndSendsResultsWithItsName) {
  FakeBroker broker;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "w", 2));
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready.has_value());
  broker.SendJob(ready->peer, MakeJob("first", 1));
  broker.SendJob(ready->peer, MakeJob("second", 2));
  EXPECT_EQ(connection.NextJob(milliseconds(5000)).value().job_id(), "first");
  EXPECT_EQ(connection.NextJob(milliseconds(5000)).value().job_id(), "second");
  EXPECT_EQ(connection.NextJob(milliseconds(10)), std::nullopt);

  v1::Result result;
  result.set_job_id("first");
  result.set_status(v1::Result::OK);
  result.set_fitness(1.5);
  connection.SendResult(result);
  std::optional<FakeBroker::Received> answer = broker.Receive();
  ASSERT_TRUE(answer && answer->message.has_result());
  EXPECT_EQ(answer->peer, ready->peer);
  EXPECT_EQ(answer->message.result().job_id(), "first");
  EXPECT_EQ(answer->message.result().worker_id(), "w");
  EXPECT_EQ(answer->message.result().protocol_version(), proto::kProtocolVersion);
  EXPECT_EQ(answer->message.result().fitness(), 1.5);
  EXPECT_TRUE(WaitFor([&] { return connection.stats().results_sent == 1; }));
}

TEST(WorkerConnection, ConnectsAgainWhenTheBrokerFallsSilent) {
  FakeBroker broker;
  LogLines log;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "w", 2, &log));
  std::optional<FakeBroker::Received> first = broker.Receive();
  ASSERT_TRUE(first && first->message.has_ready());
  // The fake broker never answers: after 5 heartbeats of silence the worker starts over on a new socket.
  std::optional<FakeBroker::Received> second = broker.Receive();
  ASSERT_TRUE(second && second->message.has_ready());
  EXPECT_NE(second->peer, first->peer);
  EXPECT_EQ(connection.stats().connections, 2u);
  EXPECT_EQ(log.Count("no answer from the broker at " + broker.endpoint() + " for 0.5 s; connecting again"), 1);
}

TEST(WorkerConnection, GoodbyeFromTheBrokerDropsHeldJobsAndConnectsAgain) {
  FakeBroker broker;
  LogLines log;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "w", 2, &log));
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready.has_value());
  broker.SendJob(ready->peer, MakeJob("a", 1));
  broker.SendJob(ready->peer, MakeJob("b", 2));
  ASSERT_TRUE(WaitFor([&] { return connection.stats().jobs_received == 2; }));
  v1::BrokerToWorker goodbye;
  goodbye.set_protocol_version(proto::kProtocolVersion);
  goodbye.mutable_disconnect()->set_reason("restarting");
  broker.Send(ready->peer, goodbye);
  std::optional<FakeBroker::Received> again = broker.Receive();
  ASSERT_TRUE(again && again->message.has_ready());
  EXPECT_EQ(connection.NextJob(milliseconds(10)), std::nullopt);  // the broker requeues them, not us
  EXPECT_EQ(connection.stats().jobs_discarded, 2u);
  EXPECT_EQ(log.Count("said goodbye (restarting); connecting again (dropped 2 jobs not started"), 1);
}

TEST(WorkerConnection, DropsGarbageFromTheBrokerAndKeepsWorking) {
  FakeBroker broker;
  LogLines log;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "w", 2, &log));
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready.has_value());
  v1::BrokerToWorker wrong_version;
  wrong_version.set_protocol_version(3);
  *wrong_version.mutable_job() = MakeJob("foreign", 1);
  broker.SendFrames(ready->peer, {std::string("\xff\xfe garbage", 10)});
  broker.Send(ready->peer, wrong_version);
  broker.SendFrames(ready->peer, {"two", "frames"});
  broker.SendFrames(ready->peer, {""});  // parses, but has no version and no body
  broker.SendJob(ready->peer, MakeJob("good", 2));
  EXPECT_EQ(connection.NextJob(milliseconds(5000)).value().job_id(), "good");
  EXPECT_EQ(connection.stats().messages_dropped, 4u);
  EXPECT_EQ(log.Count("dropped a message from the broker"), 1);
}

TEST(WorkerConnection, AnswersAJobOfAnotherProtocolVersionAsInvalidInput) {
  FakeBroker broker;
  WorkerConnection connection(TestWorkerOptions(broker.endpoint(), "w", 2));
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready.has_value());
  v1::Job job = MakeJob("future", 1);
  job.set_protocol_version(9);
  broker.SendJob(ready->peer, job);
  std::optional<FakeBroker::Received> answer = broker.Receive();
  ASSERT_TRUE(answer && answer->message.has_result());
  EXPECT_EQ(answer->message.result().job_id(), "future");
  EXPECT_EQ(answer->message.result().status(), v1::Result::INVALID_INPUT);
  EXPECT_EQ(answer->message.result().message(), "job protocol version 9; this worker speaks 1");
  EXPECT_EQ(connection.NextJob(milliseconds(10)), std::nullopt);
}

TEST(WorkerConnection, HeartbeatsKeepALongJobAlive) {
  BrokerThread broker(TestBrokerOptions());
  // Each job takes three times as long as the broker waits for a silent worker.
  EchoWorker worker(TestWorkerOptions(broker.worker_endpoint(), "slow", 1), milliseconds(1500));
  runtime::BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit({MakeJob("long", 4)});
  std::optional<v1::Result> result = client.Next(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->fitness(), 8.25);
  EXPECT_EQ(result->attempts(), 1u);
  EXPECT_EQ(broker.stats().workers_lost, 0u);
  EXPECT_EQ(broker.stats().jobs_dispatched, 1u);
}

TEST(WorkerConnection, ServesANewBrokerStartedOnTheSamePort) {
  LogLines log;
  auto first = std::make_unique<BrokerThread>(TestBrokerOptions(&log));
  broker::BrokerOptions same_ports = TestBrokerOptions(&log);
  const std::string endpoint = first->worker_endpoint();
  same_ports.worker_port = std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
  EchoWorker worker(TestWorkerOptions(endpoint, "survivor", 2, &log));
  ASSERT_TRUE(WaitFor([&] { return first->stats().workers == 1; }));
  first->Stop();
  first.reset();

  BrokerThread second(same_ports);
  ASSERT_TRUE(WaitFor([&] { return second.stats().workers == 1; }));
  runtime::BatchClient client(TestClientOptions(second.client_endpoint()));
  client.Submit({MakeJob("after", 5), MakeJob("restart", 6)});
  EXPECT_EQ(Collect(client, 2).size(), 2u);
  EXPECT_EQ(worker.jobs_done(), 2);
  // 2, or 3 when the new socket reached the old broker's listener in the moment before it closed: then the new
  // broker's answer to the worker's heartbeat ("unknown worker") makes it start over once more.
  EXPECT_GE(worker.connection().stats().connections, 2u);
}

TEST(WorkerConnection, ShortJobsRaiseTheCreditAndALongOneLowersIt) {
  FakeBroker broker;
  worker::WorkerConnectionOptions options = TestWorkerOptions(broker.endpoint(), "w", 2);
  options.short_job_credit = 8;
  options.short_job = milliseconds(50);
  WorkerConnection connection(options);
  std::optional<FakeBroker::Received> ready = broker.Receive();
  ASSERT_TRUE(ready && ready->message.has_ready());
  EXPECT_EQ(ready->message.ready().credit(), 2u);
  // Jobs answered at once, one at a time: after kShortJobsToRaise of them the credit goes up, on the same socket.
  for (int i = 0; i < WorkerConnection::kShortJobsToRaise; ++i) {
    broker.SendJob(ready->peer, MakeJob("short-" + std::to_string(i), static_cast<std::uint64_t>(i)));
    v1::Job job = connection.NextJob(milliseconds(5000)).value();
    v1::Result result;
    result.set_job_id(job.job_id());
    result.set_status(v1::Result::OK);
    connection.SendResult(result);
  }
  for (int i = 0; i < WorkerConnection::kShortJobsToRaise; ++i) {
    std::optional<FakeBroker::Received> answer = broker.Receive();
    ASSERT_TRUE(answer && answer->message.has_result()) << i;
    EXPECT_EQ(answer->message.result().job_id(), "short-" + std::to_string(i));
  }
  std::optional<FakeBroker::Received> raised = broker.Receive();
  ASSERT_TRUE(raised && raised->message.has_ready());
  EXPECT_EQ(raised->peer, ready->peer);
  EXPECT_EQ(raised->message.ready().credit(), 8u);
  EXPECT_EQ(raised->message.ready().worker_id(), "w");
  EXPECT_TRUE(WaitFor([&] { return connection.stats().credit == 8; }));

  // One job that takes longer than options.short_job: back to the base credit, after its result.
  broker.SendJob(ready->peer, MakeJob("long", 99));
  v1::Job job = connection.NextJob(milliseconds(5000)).value();
  std::this_thread::sleep_for(milliseconds(80));  // the job's work
  v1::Result result;
  result.set_job_id(job.job_id());
  result.set_status(v1::Result::OK);
  connection.SendResult(result);
  std::optional<FakeBroker::Received> answer = broker.Receive();
  ASSERT_TRUE(answer && answer->message.has_result());
  EXPECT_EQ(answer->message.result().job_id(), "long");
  std::optional<FakeBroker::Received> lowered = broker.Receive();
  ASSERT_TRUE(lowered && lowered->message.has_ready());
  EXPECT_EQ(lowered->peer, ready->peer);
  EXPECT_EQ(lowered->message.ready().credit(), 2u);
  const worker::WorkerConnectionStats stats = connection.stats();
  EXPECT_EQ(stats.credit, 2u);
  EXPECT_EQ(stats.credit_changes, 2u);
  EXPECT_EQ(stats.connections, 1u);
}

TEST(WorkerConnection, RaisedCreditFallsBackWhenNoJobComesForAHeartbeat) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  EchoWorker worker(TestWorkerOptions(broker.worker_endpoint(), "quick", 2, &log));
  runtime::BatchClient client(TestClientOptions(broker.client_endpoint()));
  std::vector<v1::Job> jobs;
  for (int i = 0; i < 200; ++i) jobs.push_back(MakeJob("job-" + std::to_string(i), static_cast<std::uint64_t>(i)));
  client.Submit(std::move(jobs));
  EXPECT_EQ(Collect(client, 200).size(), 200u);
  // The jobs took microseconds each: the worker asked for its short-job credit (default 16; more than once if a
  // preempted job looked long to it on a busy machine) ...
  EXPECT_GE(log.Count("worker quick sent READY again; credit now 16"), 1);
  // ... and once the batch is over, a heartbeat interval without a job brings it back to 2.
  EXPECT_TRUE(WaitFor([&] { return worker.connection().stats().credit == 2; }));
  EXPECT_TRUE(WaitFor([&] { return log.Count("worker quick sent READY again; credit now 2") >= 1; }));
  EXPECT_EQ(worker.connection().stats().connections, 1u);
  EXPECT_EQ(broker.stats().workers_lost, 0u);
}

TEST(WorkerConnection, RejectsBadOptions) {
  EXPECT_THROW(WorkerConnection(TestWorkerOptions("", "w", 1)), std::invalid_argument);
  EXPECT_THROW(WorkerConnection(TestWorkerOptions("tcp://127.0.0.1:1", "w", 0)), std::invalid_argument);
  EXPECT_THROW(WorkerConnection(TestWorkerOptions("tcp://127.0.0.1:1", "w", 1025)), std::invalid_argument);
  worker::WorkerConnectionOptions options = TestWorkerOptions("tcp://127.0.0.1:1", "w", 1);
  options.liveness = 1;
  EXPECT_THROW(WorkerConnection{options}, std::invalid_argument);
  options = TestWorkerOptions("tcp://127.0.0.1:1", "w", 1);
  options.short_job_credit = 1025;
  EXPECT_THROW(WorkerConnection{options}, std::invalid_argument);
  for (const char* endpoint : {"127.0.0.1:5556", "udp://127.0.0.1:5556", "tcp://127.0.0.1"}) {
    EXPECT_THROW(WorkerConnection(TestWorkerOptions(endpoint, "w", 1)), std::invalid_argument) << endpoint;
  }
}

}  // namespace
}  // namespace orcs::test_support
