// A client's connection to the broker (docs/protocol.md, "Client conversation"): submits a batch of jobs and
// hands back each job's result exactly once, as results arrive. A background I/O thread heartbeats while jobs are
// outstanding, so a caller may take its time between Next() calls. When the broker falls silent or restarts, the
// client connects again and resubmits the jobs still without a result (and drops any duplicate result that
// follows), giving up with an error after reconnect_timeout. An unreachable broker is an error within
// connect_timeout, never a hang.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>
#include <zmq.hpp>

#include "base/input_error.h"
#include "base/log_sink.h"
#include "net/curve_keys.h"
#include "net/dealer_connection.h"
#include "orcs/v1/broker.pb.h"

namespace orcs::runtime {

/// Where the client connects and how patient it is.
struct BatchClientOptions {
  /// The broker's client endpoint, e.g. "tcp://127.0.0.1:5555".
  std::string endpoint;
  /// Names the batch at the broker; "" = 128 random bits from the OS, as 32 hex digits (a name others cannot
  /// guess; the batch is bound to this client's owner token either way).
  std::string batch_id;
  /// How often the client sends heartbeats while jobs are outstanding; should equal the broker's.
  std::chrono::milliseconds heartbeat_interval{1000};
  /// The broker silent for this many heartbeat intervals → connect again and resubmit.
  int liveness = 5;
  /// Submit() fails when no broker has answered this long after it was called on an idle client.
  std::chrono::milliseconds connect_timeout{3000};
  /// After the broker was lost, how long to keep connecting again before Next() fails.
  std::chrono::milliseconds reconnect_timeout{30000};
  /// A SUBMIT message holds jobs up to about this many bytes (always at least one job), so that the broker is
  /// never busy with one message for long.
  std::size_t max_submit_bytes = std::size_t{4} << 20;
  /// Where log lines (connection events, one per line, no newline) go; empty = stderr, prefixed "orcs-batch: ".
  LogSink log;
  /// How many jobs the batch will have in all, when known (0 = not said): sent with every SUBMIT so that the
  /// broker's status can show the batch's progress and time left (docs/protocol.md, "Status").
  std::uint64_t batch_size = 0;
  /// Folder of CURVE keys (docs/security.md): the client's client.key and client.pub and the broker's broker.pub.
  /// Set: the connection is encrypted and the broker must allow client.pub. "" = plain TCP.
  std::string curve_keys;
};

/// What a client has done so far. Counters only grow.
struct BatchClientStats {
  std::uint64_t connections = 0;         ///< sockets opened: 1 + the number of reconnections
  std::uint64_t submit_messages = 0;     ///< SUBMIT messages sent, resubmissions included
  std::uint64_t results = 0;             ///< results handed to the caller's queue
  std::uint64_t duplicates_dropped = 0;  ///< results for jobs already answered (after a resubmission), dropped
  std::uint64_t messages_dropped = 0;    ///< malformed or foreign messages from the broker, dropped
  std::uint64_t handshake_failures = 0;  ///< CURVE handshakes that failed (the broker refused the key, ...)
  std::uint64_t max_outstanding = 0;     ///< the most jobs outstanding (submitted, result not yet returned) at once
};

/// The broker's error: no broker answering, the broker lost for good, a rejected submission. Once a client has
/// thrown one, every later Submit() and Next() throws it again: make a new client.
class BatchClientError : public InputError {  // bad input (no broker answering, a refused batch): exit 2
 public:
  using InputError::InputError;
};

/// A client's connection to the broker, for one batch. All public functions are thread-safe.
class BatchClient {
 public:
  /// Starts the I/O thread; connects on the first Submit(). Throws std::invalid_argument for an empty endpoint,
  /// non-positive intervals or timeouts, a liveness below 2, or an endpoint ZeroMQ cannot parse;
  /// net::CurveKeyError naming the file for a missing or malformed CURVE key.
  explicit BatchClient(BatchClientOptions options);
  /// Tells the broker the client is leaving (its jobs still queued are dropped) and stops the I/O thread.
  ~BatchClient();
  BatchClient(const BatchClient&) = delete;
  BatchClient& operator=(const BatchClient&) = delete;

  /// Submits jobs to the batch and returns once the broker has accepted them. job_id must be non-empty, unique
  /// within the call and not that of a job still outstanding (else std::invalid_argument, and nothing is sent);
  /// batch_id and protocol_version are filled in here. The client keeps a job only until Next() has returned its
  /// result, so a caller that submits in a bounded window (clients/runtime/batch_session.h) keeps the client's memory
  /// bounded too; ids must still be unique over the whole batch (a result is matched to its job by id), which the
  /// client checks only among the outstanding ones. Throws BatchClientError when the broker rejects them or none
  /// answers (connect_timeout, counted from when the last SUBMIT has left, on a client with nothing outstanding; else
  /// reconnect_timeout).
  void Submit(std::vector<v1::Job> jobs);

  /// The next result, in arrival order; each submitted job's result comes exactly once. nullopt when none arrives
  /// within `timeout`, and at once when no job is outstanding. Results that arrived before an error are handed
  /// out first; then throws BatchClientError.
  std::optional<v1::Result> Next(std::chrono::milliseconds timeout);

  /// Jobs submitted whose result Next() has not returned yet.
  std::size_t outstanding() const;
  /// The batch's id (BatchClientOptions::batch_id or its default).
  const std::string& batch_id() const { return batch_id_; }
  /// The client's name in the broker's log ("<hostname>-<pid>-<n>"; a name, not a secret).
  const std::string& client_id() const { return client_id_; }
  /// The broker endpoint.
  const std::string& endpoint() const { return options_.endpoint; }
  /// A snapshot of the counters.
  BatchClientStats stats() const;

 private:
  using Clock = std::chrono::steady_clock;

  void IoLoop();
  void Serve();
  std::optional<Clock::time_point> WakeAt() const;
  /// Excuses the broker's silence while this process was stopped (see DealerConnection::ExcuseAbsence).
  void ExcuseOversleep(std::optional<Clock::time_point> wake_at);
  void SubmitTaken(std::deque<std::vector<v1::Job>>& taken, bool failed);
  void ReadBrokerMessages();
  void CheckBroker(Clock::time_point now);
  void SayGoodbye();
  void Connect();
  void Reconnect(const std::string& why);
  void SendJobs(const std::vector<const v1::Job*>& jobs, std::uint64_t submission);
  void Resubmit();
  /// Handles one message; false when it replaced the socket (stop reading the old one).
  bool OnBrokerMessage(const zmq::message_t& payload);
  void OnAccepted();
  void OnResult(v1::Result& result);
  void Fail(const std::string& message);
  bool Active() const;
  void DropMessage(const std::string& why);
  void Log(const std::string& line) const;

  const BatchClientOptions options_;
  const std::string client_id_;
  const std::string batch_id_;
  const std::string owner_token_;  ///< Submit.owner_token: 128 random bits; the batch is this client's
  /// The socket, CURVE, heartbeats, the broker's liveness; its Wake() lets Submit() and the destructor wake the
  /// I/O thread. Otherwise owned by the I/O thread.
  net::DealerConnection dealer_;

  // Owned by the I/O thread.
  std::unordered_map<std::string, v1::Job> outstanding_;  ///< submitted, no result yet: what a resubmission sends
  std::deque<std::string> order_;         ///< job ids in submission order (answered ones dropped lazily, so it
                                          ///< stays within twice outstanding_ plus a constant)
  std::deque<std::uint64_t> unanswered_;  ///< per SUBMIT sent on this socket, the submission it belongs to
  std::uint64_t latest_sent_ = 0;         ///< the newest submission sent
  bool heard_ = false;                    ///< the broker has answered since the client became active
  Clock::time_point active_since_;        ///< when the client last went from idle to active
  v1::BrokerToClient in_;                 ///< the message being read, reused

  // Shared with the callers, guarded by mutex_.
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<v1::Job>> to_submit_;  ///< from Submit(), not yet taken by the I/O thread
  std::uint64_t submissions_ = 0;               ///< Submit() calls that got past validation
  std::uint64_t accepted_through_ = 0;          ///< submissions 1..this are accepted
  std::unordered_set<std::string> outstanding_ids_;  ///< submitted jobs not yet returned by Next(): their ids
  std::deque<v1::Result> results_;              ///< arrived, not yet returned by Next()
  std::string error_;                           ///< the terminal error, once there is one
  bool stopping_ = false;
  BatchClientStats stats_;

  std::thread io_thread_;  ///< last: starts after everything above exists
};

}  // namespace orcs::runtime
