// What a broker is told (BrokerOptions) and what it reports (BrokerStats): shared by the socket-free core
// (broker_core.h) and the ZeroMQ shell (broker.h), so that the core needs no ZeroMQ header.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "base/log_sink.h"

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
  /// A client silent for its liveness period keeps its batches this much longer: its jobs run on, their results
  /// wait at the broker, and a SUBMIT with the batch's owner token (the client woke up and connected again) carries
  /// on where it stopped. After it, the batches are dropped and their running jobs revoked. A client whose connection
  /// closed, or that said DISCONNECT or CANCEL, gets no grace: nobody can come back with its token.
  std::chrono::milliseconds client_grace{60000};
  /// The most jobs one worker connection holds at once, whatever credit it asks for (Ready.credit up to 1024): a
  /// peer asking 1024 would take the queue from every other worker, and one answering each job just before its
  /// lease ends could stretch a batch to credit × lease. 16 is WorkerConnection's short-job credit.
  std::uint32_t max_credit = 16;
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
  LogSink log;
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
  /// Dispatches revoked because their batch ended early (cancelled, client gone or past its grace): each freed its
  /// worker's credit at once and sent the worker a REVOKE.
  std::uint64_t leases_revoked = 0;
  /// Batches kept for a silent client's grace period (BrokerOptions::client_grace).
  std::uint64_t batches_orphaned = 0;
  /// Orphaned batches claimed back by their client within its grace (a SUBMIT with the owner token).
  std::uint64_t batches_reclaimed = 0;
  std::uint64_t crashes = 0;                ///< CRASHED results from workers (each is retried or ends a poisonous job)
  std::uint64_t jobs_poisoned = 0;          ///< jobs finished as CRASHED after max_crashes crashes
};

}  // namespace orcs::broker
