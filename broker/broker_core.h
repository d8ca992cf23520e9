// The broker's rules without its sockets (docs/protocol.md): the queue, workers' credit and leases, lost workers,
// crashed jobs, batches and their owners, and the journal records — as events in and messages out. The ZeroMQ shell
// (broker.h) decodes what arrives and calls one On...() per message, OnTick() per heartbeat interval and Dispatch()
// at the end of each turn, always with the current time; the core never reads a clock nor touches a socket. What
// it says to peers goes through a BrokerTransport, whose sends may fail as a ROUTER's do (the peer is gone).
//
// A state machine written down as tables in docs/protocol.md ("The broker's state machine": a job, a worker, a
// client and its batches; one row per transition). The On...() entry points are the table's events; the private
// functions they call are its actions, each named after the transition it performs, as in ZeroMQ's Malamute.
// tests/broker/broker_state_table_test.cc walks every row. Implemented in broker_core.cc (workers, leases,
// dispatch) and broker_core_jobs.cc (clients, batches, the queue, the journal).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "broker/broker_journal.h"
#include "broker/broker_settings.h"
#include "broker/rate_meter.h"
#include "orcs/v1/broker.pb.h"

namespace orcs::broker {

/// How many recent jobs per worker and recent failures per batch the status keeps.
inline constexpr std::size_t kStatusHistory = 8;
/// Longest failure message the status keeps, bytes.
inline constexpr std::size_t kMaxStatusMessageBytes = 512;

/// Longest worker, client or batch id a peer may send, bytes (a longer one is refused: ids appear in log lines).
inline constexpr std::size_t kMaxIdBytes = 128;

/// Where the core's messages go. A send returns false when the peer's connection is gone; the core then treats
/// the peer as lost (a worker's jobs go elsewhere, a client is dropped) or the job as never sent.
class BrokerTransport {
 public:
  virtual ~BrokerTransport() = default;
  virtual bool SendToWorker(const std::string& worker, const v1::BrokerToWorker& message) = 0;
  virtual bool SendToClient(const std::string& client, const v1::BrokerToClient& message) = 0;
};

/// The broker's state and rules. Single-threaded: the shell's loop alone calls it.
class BrokerCore {
 public:
  using Clock = std::chrono::steady_clock;  ///< the type of the times passed in; never read here
  using TimePoint = Clock::time_point;

  /// `transport` and `journal` (null: state in memory only) must outlive the core. `options` must be valid
  /// (the shell checks them).
  BrokerCore(const BrokerOptions& options, BrokerTransport& transport, BrokerJournal* journal);

  /// Reads the journal back after a restart (docs/protocol.md, "Restarts"). Call once, before any message.
  void Restore(TimePoint now);
  /// A well-formed envelope from the worker connection `worker` (its routing id).
  void OnWorkerMessage(const std::string& worker, v1::WorkerToBroker& message, TimePoint now);
  /// A well-formed envelope from the client connection `client`; `client_key` is its CURVE key (Z85), "" without.
  void OnClientMessage(const std::string& client, const std::string& client_key, v1::ClientToBroker& message,
                       TimePoint now);
  /// Once per heartbeat interval: heartbeats out, silent peers and overdue leases lost, unclaimed batches dropped.
  void OnTick(TimePoint now);
  /// Hands queued jobs to workers with free credit. The shell calls it at the end of every turn.
  void Dispatch(TimePoint now);
  /// Tells every worker and client the broker is leaving (DISCONNECT).
  void SayGoodbye();
  /// Counts and logs (once per peer) a message the shell could not decode; `side` is "worker" or "client".
  void DropMessage(std::string_view side, const std::string& peer, const std::string& why);
  /// Counters and gauges now (handshake counters are the shell's and stay 0 here).
  BrokerStats Stats() const;
  /// What a STATUS_REQUEST from a client holding CURVE key `client_key` ("" without) is answered with
  /// (broker_core_status.cc): with CURVE on, other keys' batches show their counts only.
  v1::Status Status(const std::string& client_key, TimePoint now) const;
  /// Where workers connect, as the shell bound it: named in the status (and so in clients' "no worker" hints).
  void SetWorkerEndpoint(std::string endpoint) { worker_endpoint_ = std::move(endpoint); }

 private:
  /// A job's place in the broker: just made, waiting, held by a worker, or answered.
  enum class JobState { kNew, kQueued, kDispatched, kFinished };
  /// (batch id, job id): names a job across batches.
  using JobKey = std::pair<std::string, std::string>;

  struct Batch;
  struct JobRecord {
    v1::Job job;                      ///< as accepted (the record goes once the job is finished: FinishJob)
    /// The batch holding it, whose queued and running counts SetState keeps (a record never outlives its batch:
    /// both live in node-based maps, and a batch's records go with it).
    Batch* batch = nullptr;
    JobState state = JobState::kNew;  ///< where it is now
    std::string worker;               ///< routing id of the holding worker while kDispatched
    std::uint64_t ticket = 0;         ///< matches this job's live queue entry while kQueued
    int losses = 0;                   ///< workers lost while holding it since it was accepted
    int dispatches = 0;               ///< JOB messages sent for it since it was accepted
    std::string lost_by;              ///< names of the workers lost while holding it, ", "-separated
    int crashes = 0;                  ///< CRASHED results for it since it was accepted
    std::string crashed_by;           ///< names of the workers whose simulation it crashed, ", "-separated
    TimePoint accepted_at;            ///< when the SUBMIT holding it was accepted
    TimePoint dispatched_at;          ///< when it was last sent to a worker
    std::uint64_t lease = 0;          ///< the current dispatch's token (Job.lease) while kDispatched; 0 = none
    TimePoint lease_deadline;         ///< while kDispatched: its worker is lost unless it answered by then
  };
  /// One failure of a batch, kept for the status.
  struct Failure {
    std::string job_id;         ///< the job
    v1::Result::Status status;  ///< how it ended
    std::string message;        ///< Result.message, cut to kMaxStatusMessageBytes
    std::string worker_id;      ///< where it ran last
    TimePoint at;               ///< when its result came
  };
  struct QueueEntry {
    std::string job_id;        ///< the job, of the batch holding this entry
    std::uint64_t ticket = 0;  ///< stale unless equal to the job's current ticket
  };
  struct Batch {
    /// Routing id of the owning client's connection; "" = nobody's now: restored from the journal and not yet
    /// claimed, or orphaned by a silent client within its grace period (claim_deadline).
    std::string client;
    std::string client_id;   ///< the owning client's name (Submit.client_id), stable across its reconnections
    /// With CURVE, the owning client's public key (Z85); only it may submit to the batch. Restored from the journal
    /// (Restore), never changed by a claim. "" = opened without CURVE: then any key holding the token may submit.
    std::string client_key;
    std::string owner_token;  ///< Submit.owner_token of the SUBMIT that opened it: later SUBMITs must match
    std::unordered_map<std::string, JobRecord> jobs;  ///< its jobs without a result yet, by job id
    TimePoint claim_deadline;  ///< while unclaimed (client ""): dropped unless its client is back by then
    /// While orphaned: the connection that owned it before it fell silent. Its CANCEL or DISCONNECT still ends the
    /// batch (a client that wakes and gives up at once must not leave its jobs running for the grace period).
    std::string former_client;
    /// Its waiting jobs, front first (requeued ones go to the front); may hold stale entries (Enqueue, CompactQueue).
    std::deque<QueueEntry> queue;
    bool in_rotation = false;  ///< whether rotation_ lists it (it has queued jobs)
    /// Results of jobs that finished while nobody owned the batch (client ""), without a journal to keep them: handed
    /// to the owner when it claims the batch back and submits them again (AcceptJob). Bounded by its pending jobs.
    std::unordered_map<std::string, v1::Result> held_results;
    // For the status only (broker_core_status.cc).
    TimePoint opened_at;             ///< its first SUBMIT, or its restore from the journal
    std::uint64_t queued = 0;        ///< its jobs in state kQueued (SetState)
    std::uint64_t running = 0;       ///< its jobs in state kDispatched (SetState)
    std::uint64_t done = 0;          ///< jobs finished with status OK
    std::uint64_t failed = 0;        ///< jobs finished with another status
    std::uint64_t expected = 0;      ///< Submit.batch_size, the latest non-zero one; 0 = not said
    RateMeter finished;              ///< finished jobs over time
    std::deque<Failure> failures;    ///< its latest failures, newest first, at most kStatusHistory
  };
  /// One job a worker finished, kept for the status.
  struct FinishedJob {
    JobKey key;                 ///< batch and job
    v1::Result::Status status;  ///< how it ended
    double seconds = 0;         ///< from dispatch to result, s
    TimePoint at;               ///< when its result came
  };
  struct Worker {
    std::string name;            ///< Ready.worker_id (or the routing id in hex)
    /// How many jobs it may hold: Ready.credit, capped at BrokerOptions::max_credit.
    std::uint32_t credit = 0;
    std::set<JobKey> holding;    ///< jobs sent to it and not answered
    bool in_ready_list = false;  ///< whether ready_workers_ lists it
    TimePoint expiry;            ///< declared lost when nothing arrived from it by then
    Clock::duration liveness_period;  ///< liveness × the longer of its and the broker's heartbeat interval
    /// When the jobs it holds are due at the latest: it runs them one after another, so each new lease starts
    /// where the previous one ends.
    TimePoint busy_until;
    // For the status only (broker_core_status.cc).
    std::string host;                 ///< Ready.host
    TimePoint connected_at;           ///< its first READY on this connection
    TimePoint last_heard;             ///< when a valid message last came from it
    std::uint64_t jobs_done = 0;      ///< results accepted from it
    std::uint64_t crashes = 0;        ///< CRASHED results from it
    std::deque<FinishedJob> recent;   ///< its latest results, newest first, at most kStatusHistory
  };
  struct Client {
    std::string client_id;                    ///< Submit.client_id of its first SUBMIT
    std::unordered_set<std::string> batches;  ///< batch ids it owns
    TimePoint expiry;                         ///< declared lost when nothing arrived from it by then
    Clock::duration liveness_period;          ///< liveness × the longer of its and the broker's heartbeat interval
  };

  // Worker messages (broker_core.cc).
  void OnWorkerReady(const std::string& worker, const v1::Ready& ready);
  /// unknown → registered on a READY, or a registered worker's credit replaced on READY again.
  void RegisterWorker(const std::string& worker, const v1::Ready& ready);
  void OnWorkerResult(const std::string& worker, v1::Result& result);
  /// The answer to the lease `worker` holds on `record`: its credit back, then the job finishes or is retried.
  void AcceptResult(const std::string& worker, const JobKey& key, JobRecord& record, v1::Result& result);
  /// Why `result` is not the answer to a lease `worker` holds, or "" when it is.
  std::string LeaseProblem(const std::string& worker, const v1::Result& result, const JobRecord* record) const;
  void RefuseResult(const std::string& worker, const v1::Result& result, const std::string& why);
  /// A CRASHED result for a pending job: retried at the front of the queue, or finished as poisonous.
  void RequeueOrPoisonCrashedJob(const std::string& worker, const std::string& batch_id, Batch& batch,
                                 JobRecord& record, v1::Result& result);
  void OnWorkerHeartbeat(const std::string& worker, const v1::Heartbeat& heartbeat);
  void OnWorkerDisconnect(const std::string& worker, const v1::Disconnect& disconnect);
  /// Tells a connection the broker does not know (or no longer knows) to start over: `why` says what it did.
  void TellWorkerToReconnect(const std::string& worker, const std::string& why);

  // The clock (broker_core.cc).
  void SendHeartbeats();
  /// How long a peer that heartbeats every `declared_ms` (0 = not said) may be silent: `liveness` times the longer
  /// of its interval and the broker's, the declared one capped at kMaxPeerHeartbeat.
  Clock::duration LivenessFor(std::uint32_t declared_ms) const;
  /// Workers silent past their liveness period are lost.
  void LoseSilentWorkers();
  /// Workers holding a job past its lease's deadline are lost (their jobs go elsewhere) and told to reconnect.
  void ExpireLeases();
  /// Why `worker` is overdue on one of its leases, or "" when it is not.
  std::string OverdueLease(const Worker& worker) const;
  /// How long a worker may hold a job with this time limit (0 = the default), from when it starts on it.
  Clock::duration LeaseLength(double time_limit_seconds) const;

  // Workers and dispatch (broker_core.cc).
  /// The first ready worker still registered, or end() when there is none.
  std::list<std::string>::iterator FirstReadyWorker();
  std::list<std::string>::iterator ReadyWorkerFor(const JobRecord& record);
  /// Sends the job to the chosen worker under a new lease; false when the send failed (the worker is then lost).
  bool LeaseJob(const JobKey& key, JobRecord& record, const std::string& worker_id);
  void MakeReady(const std::string& worker_id, Worker& worker);
  /// Forgets a worker; its held jobs go back to the queue (RequeueHeldJobs). `lost`: it vanished (silent,
  /// connection closed, lease overdue) rather than said goodbye, so each of its jobs counts one more loss.
  void DropWorker(const std::string& worker, const std::string& reason, bool lost);
  /// The jobs a dropped worker held: to the front of the queue, or failed with WORKER_LOST at their last loss.
  /// Returns how many were requeued and how many failed.
  std::pair<int, int> RequeueHeldJobs(const std::string& worker_id, const Worker& worker, const std::string& reason,
                                      bool lost);
  /// Takes the batch's running jobs off their workers' accounts (their credit is free at once) and tells each worker
  /// to drop them (REVOKE with `reason`): the batch ended early and nobody waits for their results.
  void RevokeLeases(Batch& batch, const std::string& reason);
  /// After losing a worker: back to the queue, or failed with WORKER_LOST; true when requeued.
  bool RequeueOrFailLostJob(Batch& batch, JobRecord& record, const std::string& batch_id,
                            const std::string& reason);

  // Client messages (broker_core_jobs.cc).
  void OnClientSubmit(const std::string& client, const std::string& client_key, v1::Submit& submit);
  /// What forbids this SUBMIT (malformed, or someone else's batch), or "" when nothing does.
  std::string SubmitProblem(const std::string& client, const std::string& client_key, const v1::Submit& submit) const;
  void RejectSubmit(const std::string& client, const std::string& batch_id, const std::string& problem);
  /// The submitted batch, opened for this client or moved to this connection of its owner.
  Batch& ClaimBatch(const std::string& client, const std::string& client_key, const v1::Submit& submit);
  /// (none) → owned: a SUBMIT names a batch the broker does not have.
  void OpenBatch(const std::string& client, const std::string& client_key, const v1::Submit& submit, Batch& batch);
  /// orphaned or unclaimed → owned: its owner is back (a SUBMIT with its token).
  void ReclaimBatch(const std::string& client, const v1::Submit& submit, Batch& batch);
  /// owned by one connection → owned by another: its owner reconnected.
  void MoveBatch(const std::string& client, const v1::Submit& submit, Batch& batch);
  /// Queues one submitted job (or resends its stored result); true when it was accepted anew.
  bool AcceptJob(const std::string& client, const std::string& batch_id, Batch& batch, v1::Job& job);
  void OnClientHeartbeat(const std::string& client, const v1::Heartbeat& heartbeat);
  /// Tells a connection the broker does not know (or no longer knows) to connect again and submit.
  void TellClientToReconnect(const std::string& client);
  void OnClientCancel(const std::string& client, const v1::Cancel& cancel);
  /// Whether `client` owns `batch`, or owned it until it fell silent and the batch is still orphaned.
  bool OwnedOrOrphanedBy(const Batch& batch, const std::string& client) const;
  void OnClientDisconnect(const std::string& client, const v1::Disconnect& disconnect);
  /// A connection forgotten as silent says goodbye: the batches it left orphaned go now, not after their grace.
  void DropOrphanedBatches(const std::string& former_client, const std::string& reason);
  /// Answers a STATUS_REQUEST (broker_core_status.cc).
  void OnClientStatusRequest(const std::string& client, const std::string& client_key);
  /// Clients silent past their liveness period are forgotten; their batches wait for them (OrphanClient).
  void OrphanSilentClients();
  /// Orphaned or restored batches whose owner did not come back by their claim deadline are dropped.
  void DropUnclaimedBatches();

  // The journal (broker_core_jobs.cc).
  void RestoreJob(JournalJob&& stored, std::uint64_t& in_flight);
  /// Sends the result a batch held for its absent owner to `client` (and forgets it); false when there is none.
  bool ResendHeldResult(const std::string& client, Batch& batch, const std::string& job_id);
  /// Sends the journal's stored result of a finished job to `client`; false when there is none.
  bool ResendStoredResult(const std::string& client, const std::string& batch_id, const std::string& job_id);

  // The queue and batches (broker_core_jobs.cc).
  JobRecord* FindJob(const JobKey& key);  // null when its batch or the job is unknown
  bool PopQueued(JobKey& key);
  void Enqueue(const std::string& batch_id, JobRecord& record, bool at_front);
  void SetState(JobRecord& record, JobState state);  // keeps queued_count_ and the batch's counts right
  void NoteJobHeld();  // a record was added to a batch: counts it in jobs_held_ and its peak
  /// Forgets a client and its batches. `lost`: it vanished (connection closed) rather than said goodbye.
  void DropClient(const std::string& client, const std::string& reason, bool lost);
  /// A client silent past its liveness: forgotten, but its batches wait for it for BrokerOptions::client_grace
  /// (their jobs run on) before they are dropped.
  void OrphanClient(const std::string& client, const std::string& reason);
  /// Drops a batch: its queued jobs go, its running ones are revoked (`why` tells their workers).
  void DropBatch(const std::string& batch_id, const std::string& why);
  /// Drops a batch queue's stale entries when they dominate it.
  void CompactQueue(Batch& batch);
  /// Lists a batch with queued jobs in the dispatch rotation (at the back), once.
  void Rotate(const std::string& batch_id, Batch& batch);
  void FinishJob(Batch& batch, JobRecord& record, v1::Result& result);
  void FailJob(Batch& batch, JobRecord& record, v1::Result::Status status, const std::string& message);

  // The status (broker_core_status.cc).
  /// Notes a result accepted from `worker` for the job `record` of `key`, before the job ends or is retried.
  void NoteWorkerResult(Worker& worker, const JobKey& key, const JobRecord& record, v1::Result::Status status);
  /// Notes a finished job in its batch's and the broker's counts.
  void NoteFinished(Batch& batch, const JobRecord& record, const v1::Result& result);
  /// Whether the status shows `batch`'s names and jobs to a requester with CURVE key `client_key`.
  bool ShownTo(const Batch& batch, const std::string& client_key) const;
  v1::WorkerStatus DescribeWorker(const std::string& worker_id, const Worker& worker, const std::string& client_key,
                                 TimePoint now) const;
  v1::BatchStatus DescribeBatch(const std::string& batch_id, const Batch& batch, const std::string& client_key,
                                TimePoint now) const;

  // Bookkeeping (broker_core.cc).
  /// Every event starts here: the time of the event, and the broker's start at its first.
  void Advance(TimePoint now);
  void Log(const std::string& line) const;
  std::string WorkerName(const std::string& worker) const;

  const BrokerOptions options_;
  const Clock::duration liveness_period_;  ///< heartbeat_interval × liveness
  BrokerTransport& transport_;             ///< where messages to peers go
  BrokerJournal* const journal_;           ///< null without BrokerOptions::journal

  std::unordered_map<std::string, Worker> workers_;  ///< by routing id
  std::unordered_map<std::string, Client> clients_;  ///< by routing id
  std::unordered_map<std::string, Batch> batches_;   ///< by batch id
  /// Batches with waiting jobs, in dispatch order: each dispatch takes the first batch's next job and moves the batch
  /// to the back, so batches share the workers in turn (a batch of 10 behind one of 100,000 starts at once).
  std::list<std::string> rotation_;
  std::list<std::string> ready_workers_;             ///< workers with free credit, least recently served first
  std::uint64_t next_ticket_ = 1;                    ///< the ticket the next Enqueue hands out
  std::uint64_t queued_count_ = 0;                   ///< jobs in state kQueued
  std::uint64_t in_flight_count_ = 0;                ///< the sum of the workers' holding sets' sizes
  std::uint64_t jobs_held_ = 0;                      ///< records in batches_' job maps (BrokerStats::jobs_held)
  TimePoint now_;                                    ///< the time of the event being handled, as passed in
  std::unordered_set<std::string> warned_peers_;     ///< peers whose bad message was logged already
  BrokerStats counters_;                             ///< the live counters (gauges are filled by Stats())
  // For the status only.
  std::optional<TimePoint> started_at_;              ///< the first event's time (Restore's, when journalled)
  std::uint64_t done_ = 0;                           ///< jobs finished with status OK, all batches
  std::uint64_t failed_ = 0;                         ///< jobs finished with another status, all batches
  RateMeter finished_;                               ///< finished jobs over time, all batches
  std::string worker_endpoint_;                      ///< SetWorkerEndpoint()
};

}  // namespace orcs::broker
