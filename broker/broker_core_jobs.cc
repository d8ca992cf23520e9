// The core's client side: SUBMIT, HEARTBEAT, CANCEL and DISCONNECT from clients, who owns a batch, lost clients,
// the queue, finished jobs and the journal. Workers, leases and dispatch are in broker_core.cc.
#include <algorithm>
#include <optional>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "base/demand.h"
#include "broker/broker_core.h"
#include "broker/broker_text.h"
#include "proto/envelope.h"

namespace orcs::broker {
namespace {

using proto::kProtocolVersion;

constexpr std::size_t kMaxJobIdBytes = 256;      // job ids
constexpr std::size_t kMinOwnerTokenBytes = 16;  // Submit.owner_token: at least 128 bits
constexpr std::size_t kMaxOwnerTokenBytes = 64;
constexpr std::size_t kCompactSlack = 1024;  // stale queue entries tolerated beyond twice the live ones

// Compares two secrets in time that does not depend on where they differ.
bool SameSecret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (std::size_t i = 0; i < a.size(); ++i) difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  return difference == 0;
}

// What is wrong with the i-th job of a SUBMIT, or "" when nothing is; `ids` collects the job ids seen so far.
std::string CheckSubmittedJob(const v1::Submit& submit, int i, std::unordered_set<std::string_view>& ids) {
  const v1::Job& job = submit.jobs(i);
  if (job.job_id().empty()) return "job " + std::to_string(i) + ": empty job_id";
  if (job.job_id().size() > kMaxJobIdBytes) {
    return "job " + std::to_string(i) + ": job_id longer than " + std::to_string(kMaxJobIdBytes) + " bytes";
  }
  const std::string where = "job " + std::to_string(i) + " (id '" + job.job_id() + "'): ";
  if (!ids.insert(job.job_id()).second) return where + "job_id repeated within the SUBMIT";
  if (!job.batch_id().empty() && job.batch_id() != submit.batch_id()) {
    return where + "batch_id '" + job.batch_id() + "' differs from the SUBMIT's '" + submit.batch_id() + "'";
  }
  if (job.protocol_version() != kProtocolVersion) {
    return where + "protocol_version " + std::to_string(job.protocol_version()) + " (expected " +
           std::to_string(kProtocolVersion) + ")";
  }
  return "";
}

// What is wrong with a SUBMIT on its own, or "" when nothing is.
std::string CheckSubmit(const v1::Submit& submit) {
  if (submit.batch_id().empty()) return "empty batch_id";
  if (submit.client_id().empty()) return "empty client_id";
  if (submit.batch_id().size() > kMaxIdBytes) return "batch_id longer than " + std::to_string(kMaxIdBytes) + " bytes";
  if (submit.client_id().size() > kMaxIdBytes) {
    return "client_id longer than " + std::to_string(kMaxIdBytes) + " bytes";
  }
  if (submit.owner_token().size() < kMinOwnerTokenBytes || submit.owner_token().size() > kMaxOwnerTokenBytes) {
    return "owner_token of " + std::to_string(submit.owner_token().size()) + " bytes (expected " +
           std::to_string(kMinOwnerTokenBytes) + "–" + std::to_string(kMaxOwnerTokenBytes) +
           " random bytes; a client library from before leases and owner tokens?)";
  }
  std::unordered_set<std::string_view> ids;
  for (int i = 0; i < submit.jobs_size(); ++i) {
    std::string problem = CheckSubmittedJob(submit, i, ids);
    if (!problem.empty()) return problem;
  }
  return "";
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Client messages

void BrokerCore::OnClientMessage(const std::string& client, const std::string& client_key, v1::ClientToBroker& message,
                                 TimePoint now) {
  Advance(now);
  auto known = clients_.find(client);
  if (known != clients_.end()) known->second.expiry = now_ + known->second.liveness_period;
  switch (message.body_case()) {
    case v1::ClientToBroker::kSubmit: OnClientSubmit(client, client_key, *message.mutable_submit()); break;
    case v1::ClientToBroker::kHeartbeat: OnClientHeartbeat(client, message.heartbeat()); break;
    case v1::ClientToBroker::kCancel: OnClientCancel(client, message.cancel()); break;
    case v1::ClientToBroker::kDisconnect: OnClientDisconnect(client, message.disconnect()); break;
    case v1::ClientToBroker::kStatusRequest: OnClientStatusRequest(client, client_key); break;
    case v1::ClientToBroker::BODY_NOT_SET: break;  // the shell's envelope check rejects it
  }
}

void BrokerCore::OnClientSubmit(const std::string& client, const std::string& client_key, v1::Submit& submit) {
  const std::string& batch_id = submit.batch_id();
  const std::string problem = SubmitProblem(client, client_key, submit);
  if (!problem.empty()) {
    RejectSubmit(client, batch_id, problem);
    return;
  }
  Batch& batch = ClaimBatch(client, client_key, submit);
  if (submit.batch_size() > 0) batch.expected = submit.batch_size();
  const int job_count = submit.jobs_size();
  for (int i = 0; i < job_count; ++i) {
    if (AcceptJob(client, batch_id, batch, *submit.mutable_jobs(i))) ++counters_.jobs_accepted;
  }
  v1::BrokerToClient reply;
  reply.set_protocol_version(kProtocolVersion);
  v1::Accepted& accepted = *reply.mutable_accepted();
  accepted.set_batch_id(batch_id);
  accepted.set_job_count(static_cast<std::uint32_t>(job_count));
  accepted.set_queued(queued_count_);
  transport_.SendToClient(client, reply);
}

// A batch belongs to the holder of the token that opened it (and, with CURVE, to that client's key): a batch id
// and a client id are names, printed in logs; the token is a secret, never sent back nor logged.
std::string BrokerCore::SubmitProblem(const std::string& client, const std::string& client_key,
                                      const v1::Submit& submit) const {
  std::string problem = CheckSubmit(submit);
  if (!problem.empty()) return problem;
  const std::string& batch_id = submit.batch_id();
  auto batch = batches_.find(batch_id);
  if (batch != batches_.end() && !SameSecret(batch->second.owner_token, submit.owner_token())) {
    return "batch '" + batch_id + "' belongs to another client";
  }
  if (batch != batches_.end() && !batch->second.client_key.empty() && batch->second.client_key != client_key) {
    return "batch '" + batch_id + "' belongs to another client key";
  }
  auto known = clients_.find(client);
  if (known != clients_.end() && known->second.client_id != submit.client_id()) {
    return "this connection submitted as client '" + known->second.client_id + "' before";
  }
  return "";
}

void BrokerCore::RejectSubmit(const std::string& client, const std::string& batch_id, const std::string& problem) {
  ++counters_.submits_rejected;
  Log("rejected a SUBMIT from client " + Hex(client) + ": " + problem);
  v1::BrokerToClient reply;
  reply.set_protocol_version(kProtocolVersion);
  reply.mutable_error()->set_batch_id(batch_id);
  reply.mutable_error()->set_message(problem);
  transport_.SendToClient(client, reply);
}

BrokerCore::Batch& BrokerCore::ClaimBatch(const std::string& client, const std::string& client_key,
                                          const v1::Submit& submit) {
  const std::string& batch_id = submit.batch_id();
  auto [client_entry, new_client] = clients_.try_emplace(client);
  if (new_client) client_entry->second.client_id = submit.client_id();
  if (new_client || submit.heartbeat_ms() > 0) {
    client_entry->second.liveness_period = LivenessFor(submit.heartbeat_ms());
    client_entry->second.expiry = now_ + client_entry->second.liveness_period;
  }
  auto [batch_entry, new_batch] = batches_.try_emplace(batch_id);
  Batch& batch = batch_entry->second;
  if (new_batch) {
    OpenBatch(client, client_key, submit, batch);
  } else if (batch.client.empty()) {
    ReclaimBatch(client, submit, batch);
  } else if (batch.client != client) {
    MoveBatch(client, submit, batch);
  }
  client_entry->second.batches.insert(batch_id);
  return batch;
}

void BrokerCore::OpenBatch(const std::string& client, const std::string& client_key, const v1::Submit& submit,
                           Batch& batch) {
  batch.client = client;
  batch.client_id = submit.client_id();
  batch.client_key = client_key;
  batch.owner_token = submit.owner_token();
  batch.opened_at = now_;
  if (journal_) journal_->AddBatch(submit.batch_id(), submit.client_id(), submit.owner_token(), client_key);
  Log("client " + submit.client_id() + " opened batch " + submit.batch_id());
}

void BrokerCore::ReclaimBatch(const std::string& client, const v1::Submit& submit, Batch& batch) {
  batch.former_client.clear();
  batch.client = client;
  batch.client_id = submit.client_id();
  ++counters_.batches_reclaimed;
  Log("client " + submit.client_id() + " claimed batch " + submit.batch_id() + " back");
}

// The same client on a new connection (it reconnected): results go to the new one from now on.
void BrokerCore::MoveBatch(const std::string& client, const v1::Submit& submit, Batch& batch) {
  auto previous = clients_.find(batch.client);
  if (previous != clients_.end()) previous->second.batches.erase(submit.batch_id());
  batch.client = client;
  batch.client_id = submit.client_id();
  Log("batch " + submit.batch_id() + " of client " + submit.client_id() + " moved to its new connection");
}

// A job already pending stays as it is. A finished one submitted again (its client never saw the result, e.g. it
// went to a connection that has since closed, or the broker restarted) gets its stored result when the journal has
// one, and runs again otherwise.
bool BrokerCore::AcceptJob(const std::string& client, const std::string& batch_id, Batch& batch, v1::Job& job) {
  auto [entry, inserted] = batch.jobs.try_emplace(job.job_id());
  if (inserted) NoteJobHeld();
  JobRecord& record = entry->second;
  record.batch = &batch;
  ORCS_DEMAND_MSG(inserted || record.state != JobState::kFinished, "a finished job's record goes with its result");
  if (!inserted) return false;  // queued or running already: the SUBMIT repeats it
  if (ResendHeldResult(client, batch, job.job_id()) ||
      (journal_ && ResendStoredResult(client, batch_id, job.job_id()))) {
    if (inserted) {  // finished records are not kept (FinishJob): the journal has it
      batch.jobs.erase(entry);
      --jobs_held_;
    }
    return false;
  }
  record.job = std::move(job);
  record.job.set_batch_id(batch_id);
  record.job.set_attempt(0);
  record.losses = 0;
  record.dispatches = 0;
  record.lost_by.clear();
  record.crashes = 0;
  record.crashed_by.clear();
  record.accepted_at = now_;
  Enqueue(batch_id, record, false);
  return true;
}

void BrokerCore::OnClientHeartbeat(const std::string& client, const v1::Heartbeat& heartbeat) {
  auto known = clients_.find(client);
  if (known != clients_.end()) {
    if (heartbeat.interval_ms() > 0) {
      known->second.liveness_period = LivenessFor(heartbeat.interval_ms());
      known->second.expiry = now_ + known->second.liveness_period;
    }
    return;
  }
  // After a broker restart a client's socket reconnects by itself: tell it to start over and submit again.
  TellClientToReconnect(client);
}

void BrokerCore::TellClientToReconnect(const std::string& client) {
  v1::BrokerToClient reply;
  reply.set_protocol_version(kProtocolVersion);
  reply.mutable_disconnect()->set_reason("unknown client: connect again and submit the outstanding jobs");
  transport_.SendToClient(client, reply);  // a failure changes nothing: the broker holds nothing of it
}

void BrokerCore::OnClientCancel(const std::string& client, const v1::Cancel& cancel) {
  auto batch = batches_.find(cancel.batch_id());
  if (batch == batches_.end() || !OwnedOrOrphanedBy(batch->second, client)) return;
  auto owner = clients_.find(client);
  if (owner != clients_.end()) owner->second.batches.erase(cancel.batch_id());
  Log("client " + batch->second.client_id + " cancelled batch " + cancel.batch_id());
  DropBatch(cancel.batch_id(), "batch " + cancel.batch_id() + " cancelled by its client");
}

void BrokerCore::OnClientDisconnect(const std::string& client, const v1::Disconnect& disconnect) {
  if (clients_.count(client) != 0) {
    DropClient(client, "left (" + disconnect.reason() + ")", false);
    return;
  }
  DropOrphanedBatches(client, disconnect.reason());
}

void BrokerCore::DropOrphanedBatches(const std::string& former_client, const std::string& reason) {
  std::vector<std::string> orphaned;
  for (const auto& [batch_id, batch] : batches_) {
    if (batch.client.empty() && batch.former_client == former_client) orphaned.push_back(batch_id);
  }
  for (const std::string& batch_id : orphaned) {
    Log("client " + batches_.at(batch_id).client_id + " left (" + reason + "); dropped its batch " + batch_id);
    DropBatch(batch_id, "batch " + batch_id + " ended: its client left");
  }
}

bool BrokerCore::OwnedOrOrphanedBy(const Batch& batch, const std::string& client) const {
  return batch.client == client || (batch.client.empty() && batch.former_client == client);
}

void BrokerCore::OrphanSilentClients() {
  std::vector<std::pair<std::string, Clock::duration>> silent;
  for (const auto& [client, record] : clients_) {
    if (record.expiry <= now_) silent.emplace_back(client, record.liveness_period);
  }
  for (const auto& [client, period] : silent) OrphanClient(client, "silent for " + Seconds(period));
}

void BrokerCore::DropUnclaimedBatches() {
  std::vector<std::string> unclaimed;
  for (const auto& [batch_id, batch] : batches_) {
    if (batch.client.empty() && batch.claim_deadline <= now_) unclaimed.push_back(batch_id);
  }
  for (const std::string& batch_id : unclaimed) {
    ++counters_.batches_unclaimed;
    Log("batch " + batch_id + " of client " + batches_.at(batch_id).client_id +
        " dropped: its client did not come back in time");
    DropBatch(batch_id, "batch " + batch_id + " dropped: its client did not come back in time");
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The journal

// Reads the journal back after a restart. Unfinished jobs go to the queue — those that were in flight first: their
// workers are gone or will reconnect, and their late results are refused (no lease of this broker's). Finished
// jobs keep their stored results for the client, which resubmits every job it has no result for when it finds
// the broker restarted. A batch whose client is not back within two liveness periods is dropped.
void BrokerCore::Restore(TimePoint now) {
  if (journal_ == nullptr) return;
  Advance(now);
  journal_->Begin();
  for (JournalBatch& stored : journal_->Batches()) {
    Batch& batch = batches_[stored.batch_id];
    batch.client_id = std::move(stored.client_id);
    batch.owner_token = std::move(stored.owner_token);
    batch.client_key = std::move(stored.client_key);
    batch.claim_deadline = now_ + 2 * liveness_period_;
    batch.opened_at = now_;
  }
  std::uint64_t in_flight = 0;
  journal_->ForEachJob([&](JournalJob&& stored) { RestoreJob(std::move(stored), in_flight); });
  journal_->Commit();
  Log("journal " + journal_->path() + ": restored " + std::to_string(batches_.size()) + " batches, " +
      std::to_string(counters_.jobs_restored) + " jobs queued again (" + std::to_string(in_flight) +
      " of them were in flight), " + std::to_string(counters_.results_restored) + " results kept for their clients");
}

void BrokerCore::RestoreJob(JournalJob&& stored, std::uint64_t& in_flight) {
  auto batch = batches_.find(stored.batch_id);
  if (batch == batches_.end()) return;  // a job of a batch being dropped when the broker died
  if (stored.finished) {  // the journal keeps the result for a resubmission; the broker keeps no record
    ++counters_.results_restored;
    return;
  }
  const std::string job_id = stored.job.job_id();
  auto [entry, inserted] = batch->second.jobs.try_emplace(job_id);
  if (inserted) NoteJobHeld();
  JobRecord& record = entry->second;
  record.batch = &batch->second;
  record.job = std::move(stored.job);
  record.job.set_batch_id(stored.batch_id);
  record.losses = stored.losses;
  record.dispatches = stored.dispatches;
  record.lost_by = std::move(stored.lost_by);
  record.accepted_at = now_;
  in_flight += stored.dispatched ? 1 : 0;
  Enqueue(stored.batch_id, record, false);
  ++counters_.jobs_restored;
}

bool BrokerCore::ResendHeldResult(const std::string& client, Batch& batch, const std::string& job_id) {
  auto held = batch.held_results.find(job_id);
  if (held == batch.held_results.end()) return false;
  v1::BrokerToClient message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_result()->Swap(&held->second);
  batch.held_results.erase(held);
  if (transport_.SendToClient(client, message)) {
    ++counters_.results_delivered;
    ++counters_.results_resent;
  }
  return true;
}

bool BrokerCore::ResendStoredResult(const std::string& client, const std::string& batch_id,
                                    const std::string& job_id) {
  std::optional<v1::Result> stored = journal_->Result(batch_id, job_id);
  if (!stored) return false;
  v1::BrokerToClient message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_result()->Swap(&*stored);
  if (transport_.SendToClient(client, message)) {
    ++counters_.results_delivered;
    ++counters_.results_resent;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------------------
// The queue and batches

// The next job of the first batch in the rotation; the batch then goes to the back while it has more.
bool BrokerCore::PopQueued(JobKey& key) {
  while (!rotation_.empty()) {
    const std::string batch_id = std::move(rotation_.front());
    rotation_.pop_front();
    auto batch = batches_.find(batch_id);
    if (batch == batches_.end()) continue;  // dropped since it was listed
    Batch& record = batch->second;
    record.in_rotation = false;
    while (!record.queue.empty()) {
      QueueEntry entry = std::move(record.queue.front());
      record.queue.pop_front();
      auto job = record.jobs.find(entry.job_id);
      if (job == record.jobs.end()) continue;  // answered
      if (job->second.state != JobState::kQueued || job->second.ticket != entry.ticket) continue;  // stale entry
      if (record.queued > 1) Rotate(batch_id, record);  // its other jobs wait for their turn
      key = {batch_id, std::move(entry.job_id)};
      return true;
    }
  }
  return false;
}

void BrokerCore::Rotate(const std::string& batch_id, Batch& batch) {
  if (batch.in_rotation) return;
  rotation_.push_back(batch_id);
  batch.in_rotation = true;
}

BrokerCore::JobRecord* BrokerCore::FindJob(const JobKey& key) {
  auto batch = batches_.find(key.first);
  if (batch == batches_.end()) return nullptr;
  auto job = batch->second.jobs.find(key.second);
  return job == batch->second.jobs.end() ? nullptr : &job->second;
}

void BrokerCore::Enqueue(const std::string& batch_id, JobRecord& record, bool at_front) {
  SetState(record, JobState::kQueued);
  record.worker.clear();
  record.lease = 0;
  record.ticket = next_ticket_++;  // older entries of this job become stale
  if (journal_) journal_->SaveQueued(batch_id, record.job, record.ticket, record.losses, record.lost_by);
  QueueEntry entry{record.job.job_id(), record.ticket};
  Batch& batch = *record.batch;
  CompactQueue(batch);  // earlier entries of requeued jobs are stale
  if (at_front) {
    batch.queue.push_front(std::move(entry));
  } else {
    batch.queue.push_back(std::move(entry));
  }
  Rotate(batch_id, batch);
}

void BrokerCore::NoteJobHeld() {
  ++jobs_held_;
  counters_.jobs_held_peak = std::max(counters_.jobs_held_peak, jobs_held_);
}

void BrokerCore::SetState(JobRecord& record, JobState state) {
  if (record.state == JobState::kQueued) --queued_count_;
  if (state == JobState::kQueued) ++queued_count_;
  if (record.batch != nullptr) {
    if (record.state == JobState::kQueued) --record.batch->queued;
    if (record.state == JobState::kDispatched) --record.batch->running;
    if (state == JobState::kQueued) ++record.batch->queued;
    if (state == JobState::kDispatched) ++record.batch->running;
  }
  record.state = state;
}

void BrokerCore::DropClient(const std::string& client, const std::string& reason, bool lost) {
  auto entry = clients_.find(client);
  if (entry == clients_.end()) return;
  const Client record = std::move(entry->second);
  clients_.erase(entry);
  std::uint64_t pending = 0;
  for (const std::string& batch_id : record.batches) {
    auto batch = batches_.find(batch_id);
    if (batch == batches_.end() || batch->second.client != client) continue;
    for (const auto& [job_id, job] : batch->second.jobs) pending += job.state != JobState::kFinished ? 1 : 0;
    DropBatch(batch_id, "batch " + batch_id + " ended: its client " + reason);
  }
  if (!lost) {
    Log("client " + record.client_id + " " + reason +
        (pending > 0 ? "; dropped its " + std::to_string(pending) + " pending jobs" : ""));
  } else if (pending > 0) {
    ++counters_.clients_lost;
    Log("client " + record.client_id + " lost (" + reason + "); dropped its " + std::to_string(pending) +
        " pending jobs");
  } else {
    // A client stops heartbeating once it has every result: forgetting it is routine.
    Log("client " + record.client_id + " forgotten (" + reason + ", nothing pending)");
  }
}

void BrokerCore::OrphanClient(const std::string& client, const std::string& reason) {
  auto entry = clients_.find(client);
  if (entry == clients_.end()) return;
  const Client record = std::move(entry->second);
  clients_.erase(entry);
  std::uint64_t pending = 0;
  std::uint64_t orphaned = 0;
  for (const std::string& batch_id : record.batches) {
    auto batch = batches_.find(batch_id);
    if (batch == batches_.end() || batch->second.client != client) continue;
    if (batch->second.jobs.empty() && batch->second.held_results.empty()) {  // nothing to come back for
      DropBatch(batch_id, "batch " + batch_id + " ended: its client fell silent with nothing pending");
      continue;
    }
    pending += batch->second.jobs.size();
    batch->second.former_client = client;
    batch->second.client.clear();
    batch->second.claim_deadline = now_ + options_.client_grace;
    ++orphaned;
    ++counters_.batches_orphaned;
  }
  if (pending == 0) {
    // A client stops heartbeating once it has every result: forgetting it is routine.
    Log("client " + record.client_id + " forgotten (" + reason + ", nothing pending)");
    return;
  }
  ++counters_.clients_lost;
  Log("client " + record.client_id + " lost (" + reason + "); its " + std::to_string(orphaned) + " batches (" +
      std::to_string(pending) + " pending jobs) wait " + Seconds(options_.client_grace) +
      " for it to come back, then are dropped");
}

void BrokerCore::DropBatch(const std::string& batch_id, const std::string& why) {
  auto batch = batches_.find(batch_id);
  if (batch == batches_.end()) return;
  RevokeLeases(batch->second, why);
  for (auto& [job_id, record] : batch->second.jobs) SetState(record, JobState::kFinished);
  jobs_held_ -= batch->second.jobs.size();
  batches_.erase(batch);  // its queue and its rotation entry (skipped by PopQueued) go with it
  if (journal_) journal_->DropBatch(batch_id);
}

void BrokerCore::CompactQueue(Batch& batch) {
  if (batch.queue.size() <= 2 * batch.queued + kCompactSlack) return;
  std::deque<QueueEntry> live;
  for (QueueEntry& entry : batch.queue) {
    auto job = batch.jobs.find(entry.job_id);
    if (job == batch.jobs.end() || job->second.state != JobState::kQueued || job->second.ticket != entry.ticket) {
      continue;
    }
    live.push_back(std::move(entry));
  }
  batch.queue = std::move(live);
}

void BrokerCore::FinishJob(Batch& batch, JobRecord& record, v1::Result& result) {
  result.set_protocol_version(kProtocolVersion);
  result.set_batch_id(record.job.batch_id());
  result.set_job_id(record.job.job_id());
  if (result.status() == v1::Result::STATUS_UNSPECIFIED) {
    result.set_status(v1::Result::INTERNAL_ERROR);
    if (result.message().empty()) result.set_message("the worker sent a result without a status");
  }
  result.set_attempts(static_cast<std::uint32_t>(record.dispatches));
  result.mutable_timings()->set_queued_seconds(
      SecondsBetween(record.accepted_at, record.dispatches > 0 ? record.dispatched_at : now_));
  SetState(record, JobState::kFinished);
  record.worker.clear();
  record.lease = 0;
  NoteFinished(batch, record, result);
  if (journal_) journal_->SaveFinished(record.job.batch_id(), record.job.job_id(), result);
  // The record goes: a finished job needs nothing from the broker's memory, so a batch streamed through a window
  // keeps the broker's memory in proportion to its pending jobs, not to every job it ever had. A late or forged
  // result for it is refused as one for an unknown job; a resubmission of it runs again, or, with a journal,
  // gets the stored result (AcceptJob).
  const std::string job_id = record.job.job_id();
  batch.jobs.erase(job_id);  // `record` dangles from here on
  --jobs_held_;

  v1::BrokerToClient message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_result()->Swap(&result);
  // A batch nobody owns now (restored, or its client silent): the journal keeps the result until the client asks
  // again, or, without one, the batch does.
  if (batch.client.empty()) {
    if (!journal_) batch.held_results[job_id] = std::move(*message.mutable_result());
    return;
  }
  if (transport_.SendToClient(batch.client, message)) ++counters_.results_delivered;
}

void BrokerCore::FailJob(Batch& batch, JobRecord& record, v1::Result::Status status, const std::string& message) {
  v1::Result result;
  result.set_status(status);
  result.set_message(message);
  auto last = record.lost_by.rfind(", ");
  result.set_worker_id(last == std::string::npos ? record.lost_by : record.lost_by.substr(last + 2));
  FinishJob(batch, record, result);
}

}  // namespace orcs::broker
