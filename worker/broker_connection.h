// A worker's connection to the broker (docs/protocol.md, "Worker conversation"): announces the worker with its
// credit, receives jobs into a small queue the caller takes them from one at a time, sends results back, and
// heartbeats from a background I/O thread — so the broker keeps hearing from the worker while a job runs for
// minutes. When the broker falls silent or says goodbye, the connection starts over on a new socket and sends
// READY again (the jobs it held but had not handed out are dropped: the broker requeues them).
//
// Credit adapts to short jobs: a credit of 2 hides the round trip to the broker behind a running job, but a job
// much shorter than that round trip leaves the worker waiting for the next one. So after a run of short jobs
// (each answered within `short_job` of being handed out) the connection announces `short_job_credit` with a
// second READY on the same connection; the first longer job, a quiet heartbeat interval or a new connection bring
// it back to `credit`. Jobs of seconds — every A-Series simulation — never raise it.
//
// Links only the wire schema and ZeroMQ (no model/): orcs-worker translates between jobs and simulations.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <stop_token>
#include <thread>
#include <zmq.hpp>

#include "base/log_sink.h"
#include "net/curve_keys.h"
#include "net/dealer_connection.h"
#include "orcs/v1/broker.pb.h"

namespace orcs::worker {

/// Where the worker connects and how it paces itself.
struct WorkerConnectionOptions {
  /// The broker's worker endpoint, e.g. "tcp://127.0.0.1:5556".
  std::string endpoint;
  /// The worker's name in the broker's log and in Result.worker_id; "" = "<hostname>-<pid>".
  std::string worker_id;
  /// How many jobs the broker may hand this worker at once (the running one plus those waiting), 1..1024.
  /// 2 hides the round trip between two jobs.
  int credit = 2;
  /// The credit announced instead after `kShortJobsToRaise` short jobs in a row (see the top of this file);
  /// at most 1024. A value ≤ `credit` keeps the credit fixed at `credit`.
  int short_job_credit = 16;
  /// A job is short when its result is given to SendResult within this time of NextJob handing it out (measured
  /// when one job at a time is in the caller's hands, as in orcs-worker).
  std::chrono::microseconds short_job{1000};
  /// How often the worker sends heartbeats; should equal the broker's.
  std::chrono::milliseconds heartbeat_interval{1000};
  /// The broker silent for this many heartbeat intervals → a new connection and READY again.
  int liveness = 5;
  /// Where log lines (connection events, one per line, no newline) go; empty = stderr, prefixed "orcs-worker: ".
  LogSink log;
  /// Folder of CURVE keys (docs/security.md): the worker's worker.key and worker.pub and the broker's broker.pub.
  /// Set: the connection is encrypted and the broker must allow worker.pub. "" = plain TCP.
  std::string curve_keys;
};

/// What a connection has done so far. Counters only grow.
struct WorkerConnectionStats {
  std::uint64_t connections = 0;       ///< READY messages sent: 1 + the number of reconnections
  std::uint64_t jobs_received = 0;     ///< JOB messages received
  std::uint64_t jobs_discarded = 0;    ///< received jobs dropped untaken at a reconnection
  std::uint64_t results_sent = 0;      ///< RESULT messages sent
  std::uint64_t messages_dropped = 0;  ///< malformed or foreign messages from the broker, dropped
  bool broker_answering = false;       ///< whether the broker has been heard on the current connection
  std::uint32_t credit = 0;            ///< the credit last announced (READY) on the current connection
  std::uint64_t credit_changes = 0;    ///< READY messages sent on an open connection to change the credit
  std::uint64_t handshake_failures = 0;  ///< CURVE handshakes that failed (the broker refused the key, ...)
  std::uint64_t jobs_revoked = 0;        ///< jobs the broker revoked (REVOKE): dropped unstarted or stopped running
};

/// A worker's connection to the broker. All public functions are thread-safe.
class WorkerConnection {
 public:
  /// How many short jobs in a row raise the credit to `short_job_credit`.
  static constexpr int kShortJobsToRaise = 16;

  /// Starts the I/O thread, which connects and sends READY. Never blocks on the broker: a worker may start before
  /// its broker. Throws std::invalid_argument for an empty endpoint, a credit outside 1..1024, a non-positive
  /// interval, a liveness below 2, or an endpoint ZeroMQ cannot parse; net::CurveKeyError naming the file for a
  /// missing or malformed CURVE key.
  explicit WorkerConnection(WorkerConnectionOptions options);
  /// Says DISCONNECT to the broker (its jobs go back to the queue, not counted as a loss) and stops the I/O thread.
  ~WorkerConnection();
  WorkerConnection(const WorkerConnection&) = delete;
  WorkerConnection& operator=(const WorkerConnection&) = delete;

  /// The next job, oldest first; nullopt when none arrives within `timeout`. Throws std::runtime_error when the
  /// I/O thread has failed (it logs why; nothing in the protocol makes it fail).
  std::optional<v1::Job> NextJob(std::chrono::milliseconds timeout);

  /// Sends the result of a job NextJob returned (one result per job; it gives the broker back one credit).
  /// `result.job_id` and `result.batch_id` must be the job's; protocol_version and the job's lease token are set
  /// and an empty worker_id is filled in here. Returns at once: the I/O thread sends it. The result of a job the
  /// broker revoked meanwhile is dropped instead (the broker freed its credit already and waits for nothing).
  void SendResult(v1::Result result);

  /// Whether the broker revoked `job` (one NextJob returned, its result not yet given): its batch ended early, and
  /// the caller should stop it and hand SendResult whatever it has.
  bool Revoked(const v1::Job& job) const;
  /// A descriptor that is readable while a job in the caller's hands is revoked (an eventfd): poll it beside a
  /// running job to stop it at once. Owned by the connection.
  int revoked_fd() const { return revoked_fd_; }

  /// The name the worker announced (WorkerConnectionOptions::worker_id or its default).
  const std::string& worker_id() const { return worker_id_; }
  /// The broker endpoint.
  const std::string& endpoint() const { return options_.endpoint; }
  /// A snapshot of the counters.
  WorkerConnectionStats stats() const;

 private:
  /// What a message from the broker meant to the I/O loop.
  enum class Heard { kNothing, kAlive, kReconnected };

  void IoLoop(std::stop_token stop);
  void Serve();
  /// One turn of Serve(); false when the connection is stopping.
  bool ServeOnce();
  /// Sends the results given to SendResult and a changed credit; false when the connection is stopping.
  bool SendOutbox(std::deque<v1::Result>& sending);
  void ReadBrokerMessages();
  void HeartbeatAndWatchBroker();
  void Connect();
  void Reconnect(const std::string& why);
  Heard OnBrokerMessage(const zmq::message_t& payload);
  void AnswerWrongVersionJob(const v1::Job& job);
  void OnRevoke(const v1::Revoke& revoke);
  void DropMessage(const std::string& why);
  void AnnounceCredit(int credit);
  void Log(const std::string& line) const;

  const WorkerConnectionOptions options_;
  const std::string worker_id_;
  /// The socket, CURVE, heartbeats, the broker's liveness; its Wake() lets SendResult() and the destructor wake the
  /// I/O thread. Otherwise owned by the I/O thread.
  net::DealerConnection dealer_;

  // Owned by the I/O thread.
  std::stop_token stop_;                     ///< the destructor asks the I/O thread to say goodbye and end
  v1::BrokerToWorker in_;                    ///< the message being read, reused
  int announced_credit_ = 0;                 ///< the credit of the last READY on this connection
  std::uint64_t jobs_at_last_heartbeat_ = 0;  ///< stats_.jobs_received when the last heartbeat left

  // Shared with the caller's threads, guarded by mutex_.
  mutable std::mutex mutex_;
  std::condition_variable job_arrived_;
  std::deque<v1::Job> jobs_;       ///< received, not yet taken
  std::deque<v1::Result> outbox_;  ///< given to SendResult, not yet sent
  std::string failure_;  ///< why the I/O thread stopped, when it failed
  WorkerConnectionStats stats_;
  int in_hand_ = 0;                           ///< jobs NextJob handed out whose result has not been given yet
  /// Job.lease of each job NextJob handed out, by (batch id, job id), until SendResult copies it into the result:
  /// the broker accepts a result only with its dispatch's token (docs/protocol.md, "Leases").
  std::map<std::pair<std::string, std::string>, std::uint64_t> leases_;
  std::chrono::steady_clock::time_point taken_at_;  ///< when NextJob last handed out a job
  int short_in_a_row_ = 0;                    ///< short jobs since the last long one (or the last reset)
  int wanted_credit_ = 0;                     ///< the credit the I/O thread should announce
  /// Leases of jobs in the caller's hands that the broker revoked, until their SendResult; revoked_fd_ is readable
  /// while it is not empty.
  std::set<std::uint64_t> revoked_in_hand_;
  const int revoked_fd_;  ///< eventfd: see revoked_fd()

  std::jthread io_thread_;  ///< last: starts after everything above exists
};

}  // namespace orcs::worker
