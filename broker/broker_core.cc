// The core's worker side: READY, RESULT, HEARTBEAT and DISCONNECT from workers, the clock's duties, leases, lost
// workers and dispatch. The client side, batches, the queue and the journal are in broker_core_jobs.cc.
#include "broker/broker_core.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "base/demand.h"
#include "broker/broker_text.h"
#include "proto/envelope.h"
#include "proto/secure_random.h"

namespace orcs::broker {
namespace {

using proto::kProtocolVersion;

constexpr std::uint32_t kMaxCredit = 1024;  // most jobs one worker may hold (Ready.credit)
constexpr std::size_t kMaxWarnedPeers = 4096;  // bound on the "logged once" set
// A lease lasts the job's time limit × 1.5 + 2 s, plus the liveness period: longer than the worker's own watch
// (limit + 1 s + 25 %, docs/protocol.md "Crash isolation"), so a working worker reports TIMEOUT first.
constexpr double kLeaseFactor = 1.5;
constexpr double kLeaseMarginSeconds = 2.0;
// The longest heartbeat interval a peer may declare: a peer claiming an hour would keep its jobs from others for
// hours after it died.
constexpr std::chrono::seconds kMaxPeerHeartbeat{60};

}  // namespace

BrokerCore::BrokerCore(const BrokerOptions& options, BrokerTransport& transport, BrokerJournal* journal)
    : options_(options),
      liveness_period_(options_.heartbeat_interval * options_.liveness),
      transport_(transport),
      journal_(journal) {}

// ---------------------------------------------------------------------------------------------------------------
// Worker messages

void BrokerCore::OnWorkerMessage(const std::string& worker, v1::WorkerToBroker& message, TimePoint now) {
  Advance(now);
  auto known = workers_.find(worker);
  if (known != workers_.end()) {
    known->second.expiry = now_ + known->second.liveness_period;
    known->second.last_heard = now_;
  }
  switch (message.body_case()) {
    case v1::WorkerToBroker::kReady: OnWorkerReady(worker, message.ready()); break;
    case v1::WorkerToBroker::kResult: OnWorkerResult(worker, *message.mutable_result()); break;
    case v1::WorkerToBroker::kHeartbeat: OnWorkerHeartbeat(worker, message.heartbeat()); break;
    case v1::WorkerToBroker::kDisconnect: OnWorkerDisconnect(worker, message.disconnect()); break;
    case v1::WorkerToBroker::BODY_NOT_SET: break;  // the shell's envelope check rejects it
  }
}

void BrokerCore::OnWorkerReady(const std::string& worker, const v1::Ready& ready) {
  if (ready.credit() < 1 || ready.credit() > kMaxCredit) {
    DropMessage(
        "worker", worker,
        "READY with credit " + std::to_string(ready.credit()) + " (expected 1.." + std::to_string(kMaxCredit) + ")");
    return;
  }
  if (ready.worker_id().size() > kMaxIdBytes) {
    DropMessage("worker", worker,
                "READY with a worker_id of " + std::to_string(ready.worker_id().size()) + " bytes (at most " +
                    std::to_string(kMaxIdBytes) + ")");
    return;
  }
  RegisterWorker(worker, ready);
}

void BrokerCore::RegisterWorker(const std::string& worker, const v1::Ready& ready) {
  auto [entry, inserted] = workers_.try_emplace(worker);
  Worker& record = entry->second;
  record.name = ready.worker_id().empty() ? Hex(worker) : ready.worker_id();
  // A second READY changes the credit; jobs held beyond it stay held. No connection holds more than max_credit.
  record.credit = std::min(ready.credit(), options_.max_credit);
  record.liveness_period = LivenessFor(ready.heartbeat_ms());
  record.expiry = now_ + record.liveness_period;
  record.last_heard = now_;
  if (inserted) record.connected_at = now_;
  if (ready.host().size() <= kMaxIdBytes) record.host = ready.host();
  Log((inserted ? "worker " + record.name + " joined with credit "
                : "worker " + record.name + " sent READY again; credit now ") +
      std::to_string(record.credit) +
      (ready.credit() > record.credit ? " (asked for " + std::to_string(ready.credit()) + "; --max-credit)" : ""));
  if (record.in_ready_list && record.holding.size() >= record.credit) {  // a lower credit it already uses up
    ready_workers_.remove(worker);
    record.in_ready_list = false;
  }
  MakeReady(worker, record);
}

void BrokerCore::OnWorkerResult(const std::string& worker, v1::Result& result) {
  if (result.protocol_version() != kProtocolVersion) {
    DropMessage("worker", worker, "RESULT with protocol version " + std::to_string(result.protocol_version()));
    return;
  }
  const JobKey key{result.batch_id(), result.job_id()};
  JobRecord* record = FindJob(key);
  const std::string problem = LeaseProblem(worker, result, record);
  if (!problem.empty()) {
    RefuseResult(worker, result, problem);
    return;
  }
  AcceptResult(worker, key, *record, result);
}

void BrokerCore::AcceptResult(const std::string& worker, const JobKey& key, JobRecord& record, v1::Result& result) {
  Worker& holder = workers_.at(worker);
  NoteWorkerResult(holder, key, record, result.status());
  in_flight_count_ -= holder.holding.erase(key);
  if (holder.holding.empty()) holder.busy_until = now_;
  MakeReady(worker, holder);
  record.lease = 0;
  if (result.worker_id().empty()) result.set_worker_id(holder.name);
  Batch& batch = batches_.at(key.first);
  if (result.status() == v1::Result::CRASHED) {
    RequeueOrPoisonCrashedJob(worker, key.first, batch, record, result);
  } else {
    FinishJob(batch, record, result);
  }
}

std::string BrokerCore::LeaseProblem(const std::string& worker, const v1::Result& result,
                                     const JobRecord* record) const {
  // After a restart every worker's first results come this way: they are late, not lost; the worker connects again.
  if (workers_.count(worker) == 0) {
    return "from a connection that never sent READY to this broker (a worker from before a restart, or one whose "
           "jobs went elsewhere)";
  }
  if (record == nullptr) return "for a job the broker does not know (its batch ended or never existed)";
  ORCS_DEMAND_MSG(record->state != JobState::kFinished, "a finished job's record goes with its result");
  if (record->state != JobState::kDispatched || record->worker != worker) {
    return "for a job not leased to this connection";
  }
  if (result.lease() != record->lease) return "without the token of the job's current lease";
  return "";
}

// A result is accepted only from the connection holding the job's current lease, with its token: a peer cannot
// finish a job it was not given, nor a worker a job that has gone elsewhere since. The rest is counted and logged
// (once per peer: a flood of forgeries makes one line).
void BrokerCore::RefuseResult(const std::string& worker, const v1::Result& result, const std::string& why) {
  ++counters_.results_refused;
  if (warned_peers_.size() >= kMaxWarnedPeers) warned_peers_.clear();
  if (warned_peers_.insert("refused" + worker).second) {
    Log("refused a result " + why + ": job " + result.batch_id() + "/" + result.job_id() + " from worker " +
        WorkerName(worker) + " (further refused results from this peer are counted without a log line)");
  }
  if (workers_.count(worker) == 0) TellWorkerToReconnect(worker, "unknown worker: connect again and send READY");
}

void BrokerCore::RequeueOrPoisonCrashedJob(const std::string& worker, const std::string& batch_id, Batch& batch,
                              JobRecord& record, v1::Result& result) {
  ++counters_.crashes;
  ++record.crashes;
  const std::string name = result.worker_id().empty() ? WorkerName(worker) : result.worker_id();
  record.crashed_by += (record.crashed_by.empty() ? "" : ", ") + name;
  const std::string job = batch_id + "/" + record.job.job_id();
  if (record.crashes >= options_.max_crashes) {
    ++counters_.jobs_poisoned;
    const std::string poisonous =
        "poisonous: crashed " + std::to_string(record.crashes) + " workers (" + record.crashed_by + ")";
    Log("job " + job + " " + poisonous + "; not retried");
    result.set_message(poisonous + "; the last: " + result.message());
    FinishJob(batch, record, result);
    return;
  }
  Log("job " + job + " crashed worker " + name + " (" + result.message() + "); back to the front of the queue, crash " +
      std::to_string(record.crashes) + " of " + std::to_string(options_.max_crashes));
  Enqueue(batch_id, record, true);
  ++counters_.jobs_requeued;
}

void BrokerCore::OnWorkerHeartbeat(const std::string& worker, const v1::Heartbeat& heartbeat) {
  auto known = workers_.find(worker);
  if (known != workers_.end()) {
    if (heartbeat.interval_ms() > 0) {  // a new pace, or a READY from a library that did not say it
      known->second.liveness_period = LivenessFor(heartbeat.interval_ms());
      known->second.expiry = now_ + known->second.liveness_period;
    }
    return;
  }
  // After a broker restart, a worker's socket reconnects by itself and keeps heartbeating: tell it to start over.
  TellWorkerToReconnect(worker, "unknown worker: connect again and send READY");
}

void BrokerCore::OnWorkerDisconnect(const std::string& worker, const v1::Disconnect& disconnect) {
  if (workers_.count(worker) == 0) return;
  // A worker that says goodbye did not die of its jobs: they go back to the queue without counting a loss.
  DropWorker(worker, "left (" + disconnect.reason() + ")", false);
}

void BrokerCore::TellWorkerToReconnect(const std::string& worker, const std::string& why) {
  v1::BrokerToWorker reply;
  reply.set_protocol_version(kProtocolVersion);
  reply.mutable_disconnect()->set_reason(why);
  transport_.SendToWorker(worker, reply);  // a failure changes nothing: the broker holds nothing of it
}

// ---------------------------------------------------------------------------------------------------------------
// The clock

void BrokerCore::OnTick(TimePoint now) {
  Advance(now);
  SendHeartbeats();
  LoseSilentWorkers();
  ExpireLeases();
  OrphanSilentClients();
  DropUnclaimedBatches();
}

// A heartbeat that cannot be sent means the peer's connection is gone: it is lost now, not after its liveness.
void BrokerCore::SendHeartbeats() {
  std::vector<std::string> gone_workers;
  std::vector<std::string> gone_clients;
  const auto interval_ms = static_cast<std::uint32_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(options_.heartbeat_interval).count());
  v1::BrokerToWorker to_worker;
  to_worker.set_protocol_version(kProtocolVersion);
  to_worker.mutable_heartbeat()->set_interval_ms(interval_ms);
  for (const auto& [worker, record] : workers_) {
    if (!transport_.SendToWorker(worker, to_worker)) gone_workers.push_back(worker);
  }
  v1::BrokerToClient to_client;
  to_client.set_protocol_version(kProtocolVersion);
  to_client.mutable_heartbeat()->set_interval_ms(interval_ms);
  for (const auto& [client, record] : clients_) {
    if (!transport_.SendToClient(client, to_client)) gone_clients.push_back(client);
  }
  for (const std::string& worker : gone_workers) DropWorker(worker, "connection closed", true);
  for (const std::string& client : gone_clients) DropClient(client, "connection closed", true);
}

BrokerCore::Clock::duration BrokerCore::LivenessFor(std::uint32_t declared_ms) const {
  const Clock::duration declared =
      std::min<Clock::duration>(std::chrono::milliseconds(declared_ms), kMaxPeerHeartbeat);
  return std::max<Clock::duration>(options_.heartbeat_interval, declared) * options_.liveness;
}

void BrokerCore::LoseSilentWorkers() {
  std::vector<std::pair<std::string, Clock::duration>> silent;
  for (const auto& [worker, record] : workers_) {
    if (record.expiry <= now_) silent.emplace_back(worker, record.liveness_period);
  }
  for (const auto& [worker, period] : silent) DropWorker(worker, "silent for " + Seconds(period), true);
}

void BrokerCore::ExpireLeases() {
  std::vector<std::pair<std::string, std::string>> overdue;  // worker, why
  for (const auto& [worker_id, worker] : workers_) {
    std::string why = OverdueLease(worker);
    if (!why.empty()) overdue.emplace_back(worker_id, std::move(why));
  }
  for (const auto& [worker_id, why] : overdue) {
    ++counters_.leases_expired;
    TellWorkerToReconnect(worker_id, why + ": connect again and send READY");
    DropWorker(worker_id, why, true);
  }
}

std::string BrokerCore::OverdueLease(const Worker& worker) const {
  for (const JobKey& key : worker.holding) {
    auto batch = batches_.find(key.first);
    if (batch == batches_.end()) continue;
    auto job = batch->second.jobs.find(key.second);
    if (job == batch->second.jobs.end()) continue;
    const JobRecord& record = job->second;
    if (record.state != JobState::kDispatched || record.lease_deadline > now_) continue;
    const double limit = record.job.time_limit_seconds();
    const std::string given =
        limit > 0 ? Seconds(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit)))
                  : "none given";
    return "held job " + key.first + "/" + key.second + " past its lease (time limit " + given + ", leased for " +
           Seconds(LeaseLength(limit)) + ")";
  }
  return "";
}

BrokerCore::Clock::duration BrokerCore::LeaseLength(double time_limit_seconds) const {
  // Capped at 1e9 s (32 years) so that the lease fits a steady_clock duration.
  const double limit = std::isfinite(time_limit_seconds) && time_limit_seconds > 0 ? std::min(time_limit_seconds, 1e9)
                                                                                 : options_.default_time_limit_seconds;
  return std::chrono::duration_cast<Clock::duration>(
             std::chrono::duration<double>(kLeaseFactor * limit + kLeaseMarginSeconds)) +
         liveness_period_;
}

// ---------------------------------------------------------------------------------------------------------------
// Workers and dispatch

void BrokerCore::Dispatch(TimePoint now) {
  Advance(now);
  std::vector<JobKey> deferred;  // crashed jobs waiting for a worker they have not crashed yet
  while (FirstReadyWorker() != ready_workers_.end()) {
    JobKey key;
    if (!PopQueued(key)) break;
    JobRecord& record = batches_.at(key.first).jobs.at(key.second);
    const auto chosen = ReadyWorkerFor(record);
    if (chosen == ready_workers_.end()) {
      deferred.push_back(std::move(key));
      continue;
    }
    const std::string worker_id = std::move(*chosen);
    ready_workers_.erase(chosen);
    workers_.at(worker_id).in_ready_list = false;
    if (!LeaseJob(key, record, worker_id)) {
      Enqueue(key.first, record, true);  // never reached the worker: no loss for the job
      DropWorker(worker_id, "connection closed", true);
    }
  }
  // Back to the front of the queue, in their order.
  for (auto key = deferred.rbegin(); key != deferred.rend(); ++key) {
    Enqueue(key->first, batches_.at(key->first).jobs.at(key->second), true);
  }
}

std::list<std::string>::iterator BrokerCore::FirstReadyWorker() {
  while (!ready_workers_.empty()) {  // skip workers lost since they were listed
    auto worker = workers_.find(ready_workers_.front());
    if (worker != workers_.end() && worker->second.in_ready_list) break;
    ready_workers_.pop_front();
  }
  return ready_workers_.begin();
}

// Where a job goes: the least recently served ready worker — but a job that crashed workers before goes to the
// first ready one it has not crashed yet, and waits (end()) while only workers it crashed are ready and another
// one is busy: "crashed three workers" should mean three, not one worker three times. When it has crashed every
// worker there is, any will do.
std::list<std::string>::iterator BrokerCore::ReadyWorkerFor(const JobRecord& record) {
  if (record.crashed_by.empty()) return ready_workers_.begin();
  const std::string crashed = ", " + record.crashed_by + ", ";
  const auto spared = [&](const Worker& worker) {
    return crashed.find(", " + worker.name + ", ") == std::string::npos;
  };
  for (auto candidate = ready_workers_.begin(); candidate != ready_workers_.end(); ++candidate) {
    auto worker = workers_.find(*candidate);
    if (worker != workers_.end() && worker->second.in_ready_list && spared(worker->second)) return candidate;
  }
  for (const auto& [id, worker] : workers_) {
    if (spared(worker)) return ready_workers_.end();
  }
  return ready_workers_.begin();
}

bool BrokerCore::LeaseJob(const JobKey& key, JobRecord& record, const std::string& worker_id) {
  Worker& worker = workers_.at(worker_id);
  record.job.set_attempt(static_cast<std::uint32_t>(record.losses));
  record.lease = proto::SecureRandomToken();  // unguessable: only the holder can answer for the job
  v1::BrokerToWorker message;
  message.set_protocol_version(kProtocolVersion);
  *message.mutable_job() = record.job;
  message.mutable_job()->set_lease(record.lease);
  if (!transport_.SendToWorker(worker_id, message)) return false;
  SetState(record, JobState::kDispatched);
  record.worker = worker_id;
  ++record.dispatches;
  record.dispatched_at = now_;
  worker.busy_until = std::max(worker.busy_until, now_) + LeaseLength(record.job.time_limit_seconds());
  record.lease_deadline = worker.busy_until;
  if (journal_) journal_->SaveDispatched(key.first, key.second, record.dispatches);
  if (worker.holding.insert(key).second) ++in_flight_count_;
  ++counters_.jobs_dispatched;
  MakeReady(worker_id, worker);  // to the back of the list: the least recently served worker goes first
  return true;
}

void BrokerCore::MakeReady(const std::string& worker_id, Worker& worker) {
  if (worker.in_ready_list || worker.holding.size() >= worker.credit) return;
  ready_workers_.push_back(worker_id);
  worker.in_ready_list = true;
}

void BrokerCore::DropWorker(const std::string& worker_id, const std::string& reason, bool lost) {
  auto entry = workers_.find(worker_id);
  if (entry == workers_.end()) return;
  const Worker worker = std::move(entry->second);
  workers_.erase(entry);
  in_flight_count_ -= worker.holding.size();
  if (lost) ++counters_.workers_lost;
  const auto [requeued, failed] = RequeueHeldJobs(worker_id, worker, reason, lost);
  std::string line = "worker " + worker.name + (lost ? " lost: " : " ") + reason;
  if (requeued > 0) line += "; " + std::to_string(requeued) + " jobs back to the queue";
  if (failed > 0) line += "; " + std::to_string(failed) + " jobs failed with WORKER_LOST";
  Log(line);
}

std::pair<int, int> BrokerCore::RequeueHeldJobs(const std::string& worker_id, const Worker& worker,
                                                const std::string& reason, bool lost) {
  int requeued = 0;
  int failed = 0;
  // Back to the front of the queue, keeping their order among themselves.
  for (auto key = worker.holding.rbegin(); key != worker.holding.rend(); ++key) {
    JobRecord* record = FindJob(*key);
    if (record == nullptr || record->state != JobState::kDispatched || record->worker != worker_id) continue;
    if (lost) {
      ++record->losses;
      record->lost_by += (record->lost_by.empty() ? "" : ", ") + worker.name;
    }
    const bool back = RequeueOrFailLostJob(batches_.at(key->first), *record, key->first, reason);
    requeued += back ? 1 : 0;
    failed += back ? 0 : 1;
  }
  return {requeued, failed};
}

// The batch's leases end here, not when their results would come: the workers' credit is free for other batches at
// once, and each worker hears which jobs to drop (it kills the simulation of the one it runs).
void BrokerCore::RevokeLeases(Batch& batch, const std::string& reason) {
  std::unordered_map<std::string, v1::BrokerToWorker> revokes;  // by worker
  for (auto& [job_id, record] : batch.jobs) {
    if (record.state != JobState::kDispatched) continue;
    auto worker = workers_.find(record.worker);
    if (worker != workers_.end()) {
      Worker& holder = worker->second;
      in_flight_count_ -= holder.holding.erase({record.job.batch_id(), job_id});
      if (holder.holding.empty()) holder.busy_until = now_;
      MakeReady(record.worker, holder);
      v1::BrokerToWorker& message = revokes[record.worker];
      message.mutable_revoke()->add_leases(record.lease);
    }
    ++counters_.leases_revoked;
    SetState(record, JobState::kFinished);
    record.worker.clear();
    record.lease = 0;
  }
  for (auto& [worker, message] : revokes) {
    message.set_protocol_version(kProtocolVersion);
    message.mutable_revoke()->set_reason(reason);
    // A failed send changes nothing: the worker is gone, and its lost connection is noticed at the next heartbeat.
    transport_.SendToWorker(worker, message);
  }
}

// A job that lost max_worker_losses workers fails rather than taking down worker after worker.
bool BrokerCore::RequeueOrFailLostJob(Batch& batch, JobRecord& record, const std::string& batch_id,
                               const std::string& reason) {
  if (record.losses >= options_.max_worker_losses) {
    FailJob(batch, record, v1::Result::WORKER_LOST,
            "lost " + std::to_string(record.losses) + " workers while running (" + record.lost_by +
                "); the last one: " + reason);
    return false;
  }
  Enqueue(batch_id, record, true);
  ++counters_.jobs_requeued;
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
// Bookkeeping

void BrokerCore::SayGoodbye() {
  v1::BrokerToWorker to_worker;
  to_worker.set_protocol_version(kProtocolVersion);
  to_worker.mutable_disconnect()->set_reason("broker shutting down");
  for (const auto& [worker, record] : workers_) transport_.SendToWorker(worker, to_worker);
  v1::BrokerToClient to_client;
  to_client.set_protocol_version(kProtocolVersion);
  to_client.mutable_disconnect()->set_reason("broker shutting down");
  for (const auto& [client, record] : clients_) transport_.SendToClient(client, to_client);
  Log("stopped: told " + std::to_string(workers_.size()) + " workers and " + std::to_string(clients_.size()) +
      " clients");
}

void BrokerCore::DropMessage(std::string_view side, const std::string& peer, const std::string& why) {
  ++counters_.messages_dropped;
  if (warned_peers_.size() >= kMaxWarnedPeers) warned_peers_.clear();
  if (!warned_peers_.insert(std::string(side) + peer).second) return;
  std::string name = Hex(peer);
  if (side == "worker") name = WorkerName(peer);
  Log("dropped a message from " + std::string(side) + " " + name + ": " + why +
      " (further bad messages from this peer are dropped without a log line)");
}

std::string BrokerCore::WorkerName(const std::string& worker) const {
  auto entry = workers_.find(worker);
  return entry == workers_.end() ? Hex(worker) : entry->second.name;
}

void BrokerCore::Advance(TimePoint now) {
  now_ = now;
  if (!started_at_) started_at_ = now;
}

void BrokerCore::Log(const std::string& line) const { WriteLog(options_.log, line); }

BrokerStats BrokerCore::Stats() const {
  BrokerStats snapshot = counters_;
  snapshot.workers = static_cast<int>(workers_.size());
  snapshot.clients = static_cast<int>(clients_.size());
  snapshot.batches = static_cast<int>(batches_.size());
  snapshot.queued = queued_count_;
  snapshot.in_flight = in_flight_count_;
  snapshot.jobs_held = jobs_held_;
  return snapshot;
}

}  // namespace orcs::broker
