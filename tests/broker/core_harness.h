// BrokerCore driven by hand for the core's tests (broker_core_test.cc, broker_state_table_test.cc): a core, a
// recording transport, its log and a made-up clock, with the peers' messages as one-line calls. No sockets, no
// threads, no sleeps. Worker "w" says it is "w-name", client "c" "c-name".
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "broker/broker_core.h"
#include "broker/broker_journal.h"
#include "proto/envelope.h"
#include "tests/broker/recording_transport.h"

namespace orcs::test_support {

// The options are BrokerOptions' defaults — heartbeat 1 s, liveness 5 (a peer silent for 5 s is lost), 3 losses,
// 3 crashes, credit capped at 16, a silent client's batches kept 60 s — but for the two below.
class Harness {
 public:
  /// `curve`: the core believes CURVE is on (it only looks at whether a key folder is named), and clients' keys
  /// are what Submit() and the status are given. `heartbeat`: the broker's interval (liveness stays 5).
  explicit Harness(broker::BrokerJournal* journal = nullptr, bool curve = false,
                   std::chrono::milliseconds heartbeat = std::chrono::seconds(1))
      : core_(Options(curve, heartbeat), transport_, journal) {}

  broker::BrokerOptions Options(bool curve, std::chrono::milliseconds heartbeat) {
    broker::BrokerOptions options;
    options.log = [this](std::string_view line) { log_.emplace_back(line); };
    if (curve) options.curve_keys = "keys";
    options.heartbeat_interval = heartbeat;
    return options;
  }

  /// The heartbeat interval READY, SUBMIT and HEARTBEAT declare from now on, ms (0 = not said).
  void Declare(std::uint32_t heartbeat_ms) { declared_ms_ = heartbeat_ms; }

  // Worker messages.
  void WorkerSays(const std::string& worker, v1::WorkerToBroker message) {
    message.set_protocol_version(proto::kProtocolVersion);
    core_.OnWorkerMessage(worker, message, now_);
  }
  void Ready(const std::string& worker, int credit, const std::string& host = "") {
    ReadyAs(worker, worker + "-name", credit, host);
  }
  void ReadyAs(const std::string& worker, const std::string& name, int credit, const std::string& host = "") {
    v1::WorkerToBroker message;
    message.mutable_ready()->set_host(host);
    message.mutable_ready()->set_worker_id(name);
    message.mutable_ready()->set_credit(static_cast<std::uint32_t>(credit));
    message.mutable_ready()->set_heartbeat_ms(declared_ms_);
    WorkerSays(worker, message);
  }
  void WorkerHeartbeat(const std::string& worker) { WorkerHeartbeat(worker, declared_ms_); }
  void WorkerHeartbeat(const std::string& worker, std::uint32_t interval_ms) {
    v1::WorkerToBroker message;
    message.mutable_heartbeat()->set_interval_ms(interval_ms);
    WorkerSays(worker, message);
  }
  void WorkerDisconnect(const std::string& worker, const std::string& reason) {
    v1::WorkerToBroker message;
    message.mutable_disconnect()->set_reason(reason);
    WorkerSays(worker, message);
  }
  /// A RESULT for `job` with its lease's token, fitness 1.5.
  void Answer(const std::string& worker, const v1::Job& job, v1::Result::Status status = v1::Result::OK,
              const std::string& text = "") {
    v1::WorkerToBroker message;
    v1::Result& result = *message.mutable_result();
    result.set_protocol_version(proto::kProtocolVersion);
    result.set_batch_id(job.batch_id());
    result.set_job_id(job.job_id());
    result.set_lease(job.lease());
    result.set_status(status);
    result.set_message(text);
    result.set_fitness(1.5);
    WorkerSays(worker, message);
  }
  /// Answers the n-th JOB sent to `worker`.
  void AnswerNth(const std::string& worker, std::size_t n, v1::Result::Status status = v1::Result::OK,
                 const std::string& text = "") {
    Answer(worker, transport_.Jobs(worker).at(n), status, text);
  }

  // Client messages.
  void ClientSays(const std::string& client, v1::ClientToBroker message, const std::string& key = "") {
    message.set_protocol_version(proto::kProtocolVersion);
    core_.OnClientMessage(client, key, message, now_);
  }
  void Submit(const std::string& client, const std::string& batch, const std::vector<v1::Job>& jobs,
              const std::string& token = kToken, std::uint64_t batch_size = 0, const std::string& key = "") {
    SubmitAs(client, client + "-name", batch, jobs, token, batch_size, key);
  }
  void SubmitAs(const std::string& client, const std::string& name, const std::string& batch,
                const std::vector<v1::Job>& jobs, const std::string& token = kToken, std::uint64_t batch_size = 0,
                const std::string& key = "") {
    v1::ClientToBroker message;
    v1::Submit& submit = *message.mutable_submit();
    submit.set_batch_id(batch);
    submit.set_client_id(name);
    submit.set_owner_token(token);
    for (const v1::Job& job : jobs) *submit.add_jobs() = job;
    submit.set_batch_size(batch_size);
    submit.set_heartbeat_ms(declared_ms_);
    ClientSays(client, message, key);
  }
  void ClientHeartbeat(const std::string& client) {
    v1::ClientToBroker message;
    message.mutable_heartbeat()->set_interval_ms(declared_ms_);
    ClientSays(client, message);
  }
  void Cancel(const std::string& client, const std::string& batch) {
    v1::ClientToBroker message;
    message.mutable_cancel()->set_batch_id(batch);
    ClientSays(client, message);
  }
  void ClientDisconnect(const std::string& client, const std::string& reason) {
    v1::ClientToBroker message;
    message.mutable_disconnect()->set_reason(reason);
    ClientSays(client, message);
  }
  /// The STATUS a STATUS_REQUEST from connection `asker` with CURVE key `key` is answered with.
  v1::Status AskStatus(const std::string& asker, const std::string& key = "") {
    v1::ClientToBroker message;
    message.mutable_status_request();
    ClientSays(asker, message, key);
    const v1::BrokerToClient answer = transport_.LastToClient(asker);
    EXPECT_TRUE(answer.has_status());
    return answer.status();
  }

  // The clock.
  void Advance(std::chrono::steady_clock::duration by) { now_ += by; }
  void Dispatch() { core_.Dispatch(now_); }
  void Tick() { core_.OnTick(now_); }
  /// `n` seconds, one at a time: the `alive` workers and clients heartbeat each second, then the clock's duties run.
  void Pass(int n, const std::vector<std::string>& alive_workers, const std::vector<std::string>& alive_clients) {
    for (int second = 0; second < n; ++second) {
      Advance(std::chrono::seconds(1));
      for (const std::string& worker : alive_workers) WorkerHeartbeat(worker);
      for (const std::string& client : alive_clients) ClientHeartbeat(client);
      Tick();
    }
  }
  /// `n` seconds with worker "w" and client "c" heartbeating.
  void PassSecondsWithEveryoneAlive(int n) { Pass(n, {"w"}, {"c"}); }
  /// `n` seconds with worker "w" heartbeating and the clients silent (stopped).
  void PassSecondsWithTheClientSilent(int n) { Pass(n, {"w"}, {}); }

  // What the core shows.
  broker::BrokerStats Stats() const { return core_.Stats(); }
  /// The status entry of the worker named `name`, or none when it is not registered.
  std::optional<v1::WorkerStatus> WorkerEntry(const std::string& name) const {
    const v1::Status status = core_.Status("", now_);
    for (const v1::WorkerStatus& worker : status.worker_list()) {
      if (worker.worker_id() == name) return worker;
    }
    return std::nullopt;
  }
  /// The status entry of batch `batch`, or none when the broker does not have it.
  std::optional<v1::BatchStatus> BatchEntry(const std::string& batch) const {
    const v1::Status status = core_.Status("", now_);
    for (const v1::BatchStatus& entry : status.batch_list()) {
      if (entry.batch_id() == batch) return entry;
    }
    return std::nullopt;
  }
  /// Whether a log line holds `needle`.
  bool Logged(const std::string& needle) const {
    for (const std::string& line : log_) {
      if (line.find(needle) != std::string::npos) return true;
    }
    return false;
  }

  RecordingTransport transport_;
  std::vector<std::string> log_;
  broker::BrokerCore::TimePoint now_ = broker::BrokerCore::TimePoint{} + std::chrono::hours(1);  ///< the made-up clock
  std::uint32_t declared_ms_ = 0;  ///< Declare()
  broker::BrokerCore core_;
};

}  // namespace orcs::test_support
