// Peers for broker tests, all on real ZeroMQ sockets on 127.0.0.1 with ephemeral ports: the broker on its own
// thread, echo workers built on the real WorkerConnection, and raw DEALER sockets that speak the protocol by hand
// (or fail to, on purpose). Plus WaitFor, the bounded poll every test uses instead of sleeping.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "broker/broker.h"
#include "clients/runtime/batch_client.h"
#include "net/curve_keys.h"
#include "orcs/v1/broker.pb.h"
#include "worker/broker_connection.h"

namespace orcs::test_support {

/// The heartbeat of every test peer: a peer silent for kTestLiveness of them (0.5 s) is lost.
inline constexpr std::chrono::milliseconds kTestHeartbeat{100};
inline constexpr int kTestLiveness = 5;

/// Log lines collected from a broker or connection, thread-safe.
class LogLines {
 public:
  /// A sink for BrokerOptions::log and friends; the LogLines must outlive whatever uses it.
  std::function<void(std::string_view)> Sink();
  std::vector<std::string> lines() const;
  /// How many lines contain `needle`.
  int Count(std::string_view needle) const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> lines_;
};

/// Loopback, ephemeral ports, the test heartbeat; log lines go to `log` (printed on stderr when null).
broker::BrokerOptions TestBrokerOptions(LogLines* log = nullptr);
/// A worker connection to `endpoint` with the test heartbeat, logging into `log` (stderr when null).
worker::WorkerConnectionOptions TestWorkerOptions(const std::string& endpoint, const std::string& name, int credit,
                                                  LogLines* log = nullptr);
/// A batch client of `endpoint` with the test heartbeat and short timeouts, logging into `log`.
runtime::BatchClientOptions TestClientOptions(const std::string& endpoint, LogLines* log = nullptr);

/// Polls `condition` every 2 ms until it holds or `limit` has passed; returns whether it held.
bool WaitFor(const std::function<bool()>& condition, std::chrono::milliseconds limit = std::chrono::seconds(10));

/// A TCP port on 127.0.0.1 that was free a moment ago.
int FreePort();

/// A job EchoWorker answers predictably: id `id`, seed `seed`, a genome of one number.
v1::Job MakeJob(const std::string& id, std::uint64_t seed);
/// The fitness EchoWorker reports for `job`: 2 × seed + 0.25.
double EchoFitness(const v1::Job& job);

/// A Broker running on its own thread; the destructor stops it and joins.
class BrokerThread {
 public:
  explicit BrokerThread(broker::BrokerOptions options);
  ~BrokerThread();
  broker::Broker& broker() { return *broker_; }
  const std::string& client_endpoint() const { return broker_->client_endpoint(); }
  const std::string& worker_endpoint() const { return broker_->worker_endpoint(); }
  broker::BrokerStats stats() const { return broker_->stats(); }
  /// Stops the broker, joins its thread and closes its sockets (the ports are free again). Idempotent.
  void Stop();

 private:
  std::unique_ptr<broker::Broker> broker_;
  std::thread thread_;
};

/// A worker on its own thread, with a real WorkerConnection: answers every job with status OK, fitness
/// EchoFitness(job), message "attempt=<Job.attempt>", after `job_time` of pretend work. The destructor stops the
/// thread, then destroys the connection (which says DISCONNECT).
class EchoWorker {
 public:
  EchoWorker(worker::WorkerConnectionOptions options,
             std::chrono::milliseconds job_time = std::chrono::milliseconds(0));
  ~EchoWorker();
  int jobs_done() const { return jobs_done_.load(); }
  /// The ids of the jobs it answered, in order.
  std::vector<std::string> job_ids() const;
  worker::WorkerConnection& connection() { return *connection_; }

 private:
  std::unique_ptr<worker::WorkerConnection> connection_;
  std::chrono::milliseconds job_time_;
  std::atomic<bool> stop_{false};
  std::atomic<int> jobs_done_{0};
  mutable std::mutex mutex_;
  std::vector<std::string> job_ids_;
  std::thread thread_;
};

/// A DEALER socket speaking the protocol by hand: for fake workers that go silent, fake clients, and garbage.
class RawPeer {
 public:
  /// Connects to `endpoint`, with CURVE when `curve` is given.
  explicit RawPeer(const std::string& endpoint, const std::optional<net::CurvePeerKeys>& curve = std::nullopt);
  /// Sends one message made of `frames`.
  void SendFrames(const std::vector<std::string>& frames);
  /// Sends `message` serialised, as one frame.
  void Send(const google::protobuf::Message& message);
  /// The next message's first frame; nullopt when none arrives within `timeout`.
  std::optional<std::string> Receive(std::chrono::milliseconds timeout);
  /// The next message parsed as `Envelope`; nullopt on timeout or when it does not parse.
  template <typename Envelope>
  std::optional<Envelope> ReceiveEnvelope(std::chrono::milliseconds timeout) {
    std::optional<std::string> bytes = Receive(timeout);
    Envelope envelope;
    if (!bytes || !envelope.ParseFromString(*bytes)) return std::nullopt;
    return envelope;
  }
  /// Closes the socket at once, saying nothing (a crashed peer).
  void Close();

 private:
  zmq::context_t context_;
  zmq::socket_t socket_;
};

/// READY from a fake worker.
v1::WorkerToBroker ReadyMessage(const std::string& name, int credit);
/// HEARTBEAT from a fake worker.
v1::WorkerToBroker WorkerHeartbeat();
/// RESULT for `job` from a fake worker: status OK, fitness EchoFitness(job), worker id `name`.
v1::WorkerToBroker ResultMessage(const v1::Job& job, const std::string& name);  // with the job's lease token
/// Waits for the next JOB on a fake worker, heartbeating every kTestHeartbeat meanwhile; nullopt after `limit`.
std::optional<v1::Job> AwaitJob(RawPeer& worker, std::chrono::milliseconds limit = std::chrono::seconds(10));

/// The next message to a fake worker that is not a HEARTBEAT; nullopt after `limit`.
std::optional<v1::BrokerToWorker> NextNonHeartbeat(RawPeer& worker,
                                                   std::chrono::milliseconds limit = std::chrono::seconds(5));

/// Takes results from `client` until `count` have come or `limit` has passed.
std::vector<v1::Result> Collect(runtime::BatchClient& client, std::size_t count,
                                std::chrono::milliseconds limit = std::chrono::seconds(20));

}  // namespace orcs::test_support
