// The broker: takes batches of jobs from clients, hands them to workers with free credit and sends each result
// back to the client that submitted the job (docs/protocol.md). Knows nothing of physics: it links only the wire
// schema, ZeroMQ and protobuf, so it runs on a head node with no ODE.
//
// One thread runs the broker (Run() until Stop()), so tests and `orcs-batch run` embed it in-process and
// `orcs-broker` runs it as a program. It is a state machine of small handlers, one per incoming message kind
// (OnWorkerReady, OnWorkerResult, ..., OnClientSubmit, ...) and one per clock tick (OnTick: heartbeats, lost
// workers, lost clients); Dispatch() then hands queued jobs to workers.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>
#include <zmq.hpp>

#include "broker/broker_journal.h"
#include "broker/zap_handler.h"
#include "orcs/v1/broker.pb.h"
#include "net/handshake_monitor.h"

namespace orcs::broker {

/// How a broker binds and paces itself.
struct BrokerOptions {
  /// Interface both sockets bind to: an IPv4 address, "*" for every interface, or an interface name.
  std::string bind_address = "127.0.0.1";
  int client_port = 0;  ///< TCP port of the client socket; 0 = an ephemeral port chosen by the system
  int worker_port = 0;  ///< TCP port of the worker socket; 0 = an ephemeral port chosen by the system
  /// How often the broker sends heartbeats and checks for silent peers.
  std::chrono::milliseconds heartbeat_interval{1000};
  /// A worker or client silent for this many heartbeat intervals is declared lost.
  int liveness = 5;
  /// A job whose worker was lost this many times fails with status WORKER_LOST.
  int max_worker_losses = 3;
  /// SQLite file of the journal (docs/protocol.md, "Journal"): accepted jobs, dispatches and results survive a
  /// killed broker, and a broker started on the same file resumes. "" = state in memory only.
  std::string journal;
  /// A job whose simulation crashed this many workers (CRASHED results) is poisonous: it fails with CRASHED.
  int max_crashes = 3;
  /// Lease of a job without a time limit (Job.time_limit_seconds 0): the limit the lease assumes, s. The client
  /// libraries always give a limit derived from the simulated duration; this covers other clients.
  double default_time_limit_seconds = 3600;
  /// Where log lines (one event each, no newline) go; empty = stderr, prefixed "orcs-broker: ".
  std::function<void(std::string_view)> log;
  /// Folder of CURVE keys (docs/security.md): broker.key, broker.pub, allowed_workers/*.pub, allowed_clients/*.pub.
  /// Set: both sockets are CURVE servers that accept only the allowed keys of their side. "" = plain TCP.
  std::string curve_keys;
};

/// Counters and gauges of a running broker, for tests and monitoring. Counters only grow.
struct BrokerStats {
  int workers = 0;                          ///< registered workers now
  int clients = 0;                          ///< registered clients now
  int batches = 0;                          ///< live batches now
  std::uint64_t queued = 0;                 ///< jobs waiting for a worker now
  std::uint64_t in_flight = 0;              ///< jobs held by workers now
  /// Jobs the broker keeps a record of now: those of live batches without a result yet (queued, in flight or
  /// waiting for their restored batch's client). A finished job is forgotten at once, so this follows the
  /// clients' windows, not the size of their batches.
  std::uint64_t jobs_held = 0;
  std::uint64_t jobs_held_peak = 0;         ///< the most jobs held at once since the broker started
  std::uint64_t jobs_accepted = 0;          ///< jobs accepted from SUBMITs (a resubmitted finished job counts again)
  std::uint64_t jobs_dispatched = 0;        ///< JOB messages sent to workers
  std::uint64_t jobs_requeued = 0;          ///< jobs put back at the front of the queue after their worker left
  std::uint64_t results_delivered = 0;      ///< RESULT messages sent to clients (WORKER_LOST ones included)
  /// Worker results refused: not from the connection holding the job's current lease, or without its token —
  /// forged, late (after a lost worker's jobs went elsewhere), duplicate, or for a job nobody waits for.
  std::uint64_t results_refused = 0;
  std::uint64_t leases_expired = 0;         ///< dispatches whose worker held the job past its lease's deadline
  std::uint64_t workers_lost = 0;           ///< workers declared lost (silent or connection closed)
  std::uint64_t clients_lost = 0;           ///< clients with pending jobs declared lost (silent or connection closed)
  std::uint64_t submits_rejected = 0;       ///< SUBMITs answered with ERROR
  std::uint64_t messages_dropped = 0;       ///< incoming messages dropped as malformed, foreign or illegal
  std::uint64_t jobs_restored = 0;          ///< unfinished jobs read back from the journal and queued again
  std::uint64_t results_restored = 0;       ///< finished jobs' results read back from the journal
  std::uint64_t results_resent = 0;         ///< stored results sent again to a client that resubmitted the job
  std::uint64_t batches_unclaimed = 0;      ///< restored batches dropped because no client claimed them in time
  std::uint64_t handshakes_refused = 0;     ///< CURVE peers whose key is not allowed on the socket they knocked on
  /// Connections on either socket that failed or closed during their handshake (CURVE only): refused keys, peers
  /// without CURVE, undecryptable ones, and connections closed before the handshake ended.
  std::uint64_t handshakes_failed = 0;
  std::uint64_t crashes = 0;                ///< CRASHED results from workers (each is retried or ends a poisonous job)
  std::uint64_t jobs_poisoned = 0;          ///< jobs finished as CRASHED after max_crashes crashes
};

/// The broker. Construct (binds both sockets, throws std::runtime_error naming the endpoint when it cannot, and
/// net::CurveKeyError naming the file when a CURVE key is missing or malformed), call Run() on one thread,
/// Stop() from any thread.
class Broker {
 public:
  explicit Broker(BrokerOptions options);
  ~Broker();
  Broker(const Broker&) = delete;
  Broker& operator=(const Broker&) = delete;

  /// The endpoint clients connect to, e.g. "tcp://127.0.0.1:5555" (the actual port when 0 was asked for).
  const std::string& client_endpoint() const { return client_endpoint_; }
  /// The endpoint workers connect to.
  const std::string& worker_endpoint() const { return worker_endpoint_; }

  /// Serves until Stop(); then tells every worker and client it is leaving (DISCONNECT) and closes its sockets.
  /// Call once.
  void Run();
  /// Makes Run() return soon. Thread-safe and async-signal-safe; may be called before Run().
  void Stop();

  /// A snapshot of the counters, taken at the end of the broker's last loop iteration. Thread-safe.
  BrokerStats stats() const;

 private:
  using Clock = std::chrono::steady_clock;
  /// A job's place in the broker: just made, waiting, held by a worker, or answered.
  enum class JobState { kNew, kQueued, kDispatched, kFinished };
  /// (batch id, job id): names a job across batches.
  using JobKey = std::pair<std::string, std::string>;

  struct JobRecord {
    v1::Job job;  ///< as accepted (the record goes once the job is finished: FinishJob)
    JobState state = JobState::kNew;
    std::string worker;               ///< routing id of the holding worker while kDispatched
    std::uint64_t ticket = 0;         ///< matches this job's live queue entry while kQueued
    int losses = 0;                   ///< workers lost while holding it since it was accepted
    int dispatches = 0;               ///< JOB messages sent for it since it was accepted
    std::string lost_by;              ///< names of the workers lost while holding it, ", "-separated
    int crashes = 0;                  ///< CRASHED results for it since it was accepted
    std::string crashed_by;           ///< names of the workers whose simulation it crashed, ", "-separated
    Clock::time_point accepted_at;    ///< when the SUBMIT holding it was accepted
    Clock::time_point dispatched_at;  ///< when it was last sent to a worker
    std::uint64_t lease = 0;          ///< the current dispatch's token (Job.lease) while kDispatched; 0 = none
    Clock::time_point lease_deadline;  ///< while kDispatched: its worker is lost unless it answered by then
  };
  struct Batch {
    std::string client;      ///< routing id of the owning client's connection; "" = restored, not yet claimed
    std::string client_id;   ///< the owning client's name (Submit.client_id), stable across its reconnections
    /// With CURVE, the owning client's public key (Z85); only it may submit to the batch. "" = not yet known
    /// (a batch restored from the journal, which does not record keys): the first client to claim it sets it.
    std::string client_key;
    std::string owner_token;  ///< Submit.owner_token of the SUBMIT that opened it: later SUBMITs must match
    std::unordered_map<std::string, JobRecord> jobs;  ///< its jobs without a result yet, by job id
    Clock::time_point claim_deadline;  ///< restored batches: dropped unless their client is back by then
  };
  struct Worker {
    std::string name;            ///< Ready.worker_id (or the routing id in hex)
    std::uint32_t credit = 0;    ///< Ready.credit: how many jobs it may hold
    std::set<JobKey> holding;    ///< jobs sent to it and not answered
    bool in_ready_list = false;  ///< whether ready_workers_ lists it
    Clock::time_point expiry;    ///< declared lost when nothing arrived from it by then
    /// When the jobs it holds are due at the latest: it runs them one after another, so each new lease starts
    /// where the previous one ends.
    Clock::time_point busy_until;
  };
  struct Client {
    std::string client_id;                    ///< Submit.client_id of its first SUBMIT
    std::unordered_set<std::string> batches;  ///< batch ids it owns
    Clock::time_point expiry;                 ///< declared lost when nothing arrived from it by then
  };
  struct QueueEntry {
    std::string batch_id;
    std::string job_id;
    std::uint64_t ticket = 0;  ///< stale unless equal to the job's current ticket
  };

  // CURVE.
  void EnableCurve();
  void ReadHandshakeFailures(net::HandshakeMonitor& monitor, const std::string& side);

  // Incoming traffic.
  void ReceiveWorkerMessages();
  void ReceiveClientMessages();
  void OnWorkerMessage(const std::string& worker, zmq::message_t& payload);
  void OnWorkerReady(const std::string& worker, const v1::Ready& ready);
  void OnWorkerResult(const std::string& worker, v1::Result& result);
  /// Why `result` is not the answer to a lease `worker` holds, or "" when it is.
  std::string LeaseProblem(const std::string& worker, const v1::Result& result, const JobRecord* record) const;
  void RefuseResult(const std::string& worker, const v1::Result& result, const std::string& why);
  /// A CRASHED result for a pending job: retried at the front of the queue, or finished as poisonous.
  void OnJobCrashed(const std::string& worker, const std::string& batch_id, Batch& batch, JobRecord& record,
                    v1::Result& result);
  void OnWorkerHeartbeat(const std::string& worker);
  void OnWorkerDisconnect(const std::string& worker, const v1::Disconnect& disconnect);
  void OnClientMessage(const std::string& client, zmq::message_t& payload);
  void OnClientSubmit(const std::string& client, v1::Submit& submit);
  void OnClientHeartbeat(const std::string& client);
  void OnClientCancel(const std::string& client, const v1::Cancel& cancel);
  void OnClientDisconnect(const std::string& client, const v1::Disconnect& disconnect);

  // The clock.
  void OnTick(Clock::time_point now);
  void SendHeartbeats();
  void PurgeLostWorkers(Clock::time_point now);
  void PurgeLostClients(Clock::time_point now);
  void PurgeUnclaimedBatches(Clock::time_point now);
  /// Workers holding a job past its lease's deadline are lost (their jobs go elsewhere) and told to reconnect.
  void ExpireLeases(Clock::time_point now);
  /// How long a worker may hold a job with this time limit (0 = the default), from when it starts on it.
  Clock::duration LeaseLength(double time_limit_seconds) const;

  // The journal.
  void Restore();
  /// Sends the journal's stored result of a finished job to `client`; false when there is none.
  bool ResendStoredResult(const std::string& client, const std::string& batch_id, const std::string& job_id);

  // Moving jobs.
  JobRecord* FindJob(const JobKey& key);  // null when its batch or the job is unknown
  void Dispatch();
  bool PopQueued(JobKey& key);
  std::list<std::string>::iterator ReadyWorkerFor(const JobRecord& record);
  void Enqueue(const std::string& batch_id, JobRecord& record, bool at_front);
  void SetState(JobRecord& record, JobState state);  // keeps queued_count_ right
  void NoteJobHeld();  // a record was added to a batch: counts it in jobs_held_ and its peak
  void LoseWorker(const std::string& worker, const std::string& reason, bool counts_as_loss);
  /// Forgets a client and its batches. `lost`: it vanished (silent, connection closed) rather than said goodbye.
  void DropClient(const std::string& client, const std::string& reason, bool lost);
  void DropBatch(const std::string& batch_id);
  void FinishJob(Batch& batch, JobRecord& record, v1::Result& result);
  void FailJob(Batch& batch, JobRecord& record, v1::Result::Status status, const std::string& message);
  void MakeReady(const std::string& worker_id, Worker& worker);

  // Outgoing traffic; false when the peer's connection is gone.
  bool SendToWorker(const std::string& worker, const v1::BrokerToWorker& message);
  bool SendToClient(const std::string& client, const v1::BrokerToClient& message);
  bool Send(zmq::socket_t& socket, const std::string& peer, const google::protobuf::Message& message);
  void SayGoodbye();

  void DropMessage(std::string_view side, const std::string& peer, const std::string& why);
  /// Writes one log line; control characters (a peer's newline, escape sequences) are printed escaped, and the
  /// line is cut at kMaxLogLine bytes, so that no peer can forge or flood log lines.
  void Log(const std::string& line) const;
  std::string WorkerName(const std::string& worker) const;
  void PublishStats();

  const BrokerOptions options_;
  const Clock::duration liveness_period_;  ///< heartbeat_interval × liveness
  zmq::context_t context_;
  zmq::socket_t client_socket_;
  zmq::socket_t worker_socket_;
  std::unique_ptr<ZapHandler> zap_;                          ///< with CURVE: decides who may connect
  std::unique_ptr<net::HandshakeMonitor> client_monitor_;  ///< with CURVE: failed handshakes on client_socket_
  std::unique_ptr<net::HandshakeMonitor> worker_monitor_;  ///< with CURVE: failed handshakes on worker_socket_
  std::set<std::string> warned_handshakes_;                  ///< kinds of handshake failure logged already
  std::string client_key_;  ///< with CURVE, the public key (Z85) of the client whose message is being handled
  std::string client_endpoint_;
  std::string worker_endpoint_;
  int wake_fd_ = -1;  ///< eventfd Stop() writes to, so that a blocked poll returns
  std::unique_ptr<BrokerJournal> journal_;  ///< null without BrokerOptions::journal
  std::atomic<bool> stop_requested_{false};
  bool ran_ = false;

  std::unordered_map<std::string, Worker> workers_;  ///< by routing id
  std::unordered_map<std::string, Client> clients_;  ///< by routing id
  std::unordered_map<std::string, Batch> batches_;   ///< by batch id
  std::deque<QueueEntry> queue_;                     ///< jobs waiting, front first (may hold stale entries)
  std::list<std::string> ready_workers_;             ///< workers with free credit, least recently served first
  std::uint64_t next_ticket_ = 1;
  std::uint64_t queued_count_ = 0;                ///< jobs in state kQueued
  std::uint64_t in_flight_count_ = 0;             ///< the sum of the workers' holding sets' sizes
  std::uint64_t jobs_held_ = 0;                   ///< records in batches_' job maps (BrokerStats::jobs_held)
  Clock::time_point now_;                         ///< the time of the current loop iteration
  std::unordered_set<std::string> warned_peers_;  ///< peers whose bad message was logged already
  BrokerStats counters_;                          ///< the broker thread's live counters

  v1::WorkerToBroker worker_in_;        ///< reused for parsing
  v1::ClientToBroker client_in_;        ///< reused for parsing
  std::string out_;                     ///< reused for serialising
  std::vector<zmq::message_t> frames_;  ///< reused for receiving

  mutable std::mutex stats_mutex_;
  BrokerStats stats_;  ///< the last published snapshot (guarded by stats_mutex_)
};

}  // namespace orcs::broker
