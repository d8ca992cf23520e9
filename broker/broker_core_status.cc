// The core's status (docs/protocol.md, "Status"): what each worker and batch is doing, for `orcs-broker status`
// and orcs-view's dashboard. Counts are kept as events pass (NoteWorkerResult, NoteFinished, SetState's per-batch
// queued and running counts); the answer is built only when asked, from the workers and batches alone — never by
// walking the jobs the broker holds, which may be many (a dashboard must not cost the dispatch loop).
#include <algorithm>
#include <cstdint>

#include "broker/broker_core.h"
#include "broker/broker_text.h"
#include "proto/envelope.h"

namespace orcs::broker {
namespace {

double SecondsSince(BrokerCore::TimePoint then, BrokerCore::TimePoint now) {
  return std::chrono::duration<double>(now - then).count();
}

// A count for the status: uint32 on the wire (status.proto), held at its largest value beyond.
std::uint32_t Count(std::uint64_t value) {
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(value, UINT32_MAX));
}

// Keeps `history` newest first and at most kStatusHistory long.
template <typename Entry>
void Remember(std::deque<Entry>& history, Entry entry) {
  history.push_front(std::move(entry));
  if (history.size() > kStatusHistory) history.pop_back();
}

}  // namespace

void BrokerCore::NoteWorkerResult(Worker& worker, const JobKey& key, const JobRecord& record,
                                  v1::Result::Status status) {
  ++worker.jobs_done;
  if (status == v1::Result::CRASHED) ++worker.crashes;
  Remember(worker.recent, FinishedJob{key, status, SecondsSince(record.dispatched_at, now_), now_});
}

void BrokerCore::NoteFinished(Batch& batch, const JobRecord& record, const v1::Result& result) {
  batch.finished.Add(now_);
  finished_.Add(now_);
  if (result.status() == v1::Result::OK) {
    ++batch.done;
    ++done_;
    return;
  }
  ++batch.failed;
  ++failed_;
  Remember(batch.failures, Failure{record.job.job_id(), result.status(),
                                   std::string(Utf8Prefix(result.message(), kMaxStatusMessageBytes)), result.worker_id(), now_});
}

void BrokerCore::OnClientStatusRequest(const std::string& client, const std::string& client_key) {
  v1::BrokerToClient reply;
  reply.set_protocol_version(proto::kProtocolVersion);
  *reply.mutable_status() = Status(client_key, now_);
  transport_.SendToClient(client, reply);  // a requester that has gone needs no answer
}

// Without CURVE nobody is authenticated and every batch is shown (as every name is in the broker's log); with it,
// a batch's names and jobs are its key's alone.
bool BrokerCore::ShownTo(const Batch& batch, const std::string& client_key) const {
  if (options_.curve_keys.empty()) return true;
  return !batch.client_key.empty() && batch.client_key == client_key;
}

v1::Status BrokerCore::Status(const std::string& client_key, TimePoint now) const {
  v1::Status status;
  status.set_uptime_seconds(started_at_ ? SecondsSince(*started_at_, now) : 0.0);
  status.set_worker_endpoint(worker_endpoint_);
  status.set_workers(static_cast<std::uint32_t>(workers_.size()));
  status.set_clients(static_cast<std::uint32_t>(clients_.size()));
  status.set_queued(Count(queued_count_));
  status.set_running(Count(in_flight_count_));
  status.set_done(Count(done_));
  status.set_failed(Count(failed_));
  status.set_jobs_per_second(finished_.PerSecond(now));
  status.set_workers_lost(Count(counters_.workers_lost));
  status.set_crashes(Count(counters_.crashes));
  std::uint32_t busy = 0;
  for (const auto& [id, worker] : workers_) {
    *status.add_worker_list() = DescribeWorker(id, worker, client_key, now);
    busy += worker.holding.empty() ? 0 : 1;
  }
  status.set_busy_workers(busy);
  std::sort(status.mutable_worker_list()->begin(), status.mutable_worker_list()->end(),
            [](const v1::WorkerStatus& a, const v1::WorkerStatus& b) { return a.worker_id() < b.worker_id(); });
  std::vector<const std::pair<const std::string, Batch>*> batches;
  for (const auto& entry : batches_) batches.push_back(&entry);
  std::sort(batches.begin(), batches.end(), [](const auto* a, const auto* b) {
    return a->second.opened_at != b->second.opened_at ? a->second.opened_at < b->second.opened_at
                                                      : a->first < b->first;
  });
  for (const auto* entry : batches) *status.add_batch_list() = DescribeBatch(entry->first, entry->second, client_key, now);
  return status;
}

v1::WorkerStatus BrokerCore::DescribeWorker(const std::string& worker_id, const Worker& worker,
                                            const std::string& client_key, TimePoint now) const {
  v1::WorkerStatus out;
  out.set_worker_id(worker.name);
  out.set_host(worker.host);
  out.set_busy(!worker.holding.empty());
  out.set_holding(static_cast<std::uint32_t>(worker.holding.size()));
  out.set_credit(worker.credit);
  out.set_jobs_done(Count(worker.jobs_done));
  out.set_crashes(Count(worker.crashes));
  out.set_last_heard_seconds(SecondsSince(worker.last_heard, now));
  out.set_connected_seconds(SecondsSince(worker.connected_at, now));
  // The job it runs is the one it has held longest: a worker runs its jobs one after another.
  const JobKey* current = nullptr;
  TimePoint since;
  for (const JobKey& key : worker.holding) {
    auto batch = batches_.find(key.first);
    if (batch == batches_.end()) continue;
    auto job = batch->second.jobs.find(key.second);
    if (job == batch->second.jobs.end()) continue;
    // A job of a batch its client dropped and submitted again: the worker still runs the old one, whose result
    // will be refused; the new record is another's or queued.
    if (job->second.state != JobState::kDispatched || job->second.worker != worker_id) continue;
    if (current == nullptr || job->second.dispatched_at < since) {
      current = &key;
      since = job->second.dispatched_at;
    }
  }
  if (current != nullptr) {
    out.set_current_seconds(SecondsSince(since, now));
    if (ShownTo(batches_.at(current->first), client_key)) {
      out.set_current_batch_id(current->first);
      out.set_current_job_id(current->second);
    }
  }
  for (const FinishedJob& finished : worker.recent) {
    v1::RecentJob& job = *out.add_recent_jobs();
    auto batch = batches_.find(finished.key.first);
    // A finished batch is gone from the broker: its names are shown only where nobody is authenticated.
    const bool shown = batch != batches_.end() ? ShownTo(batch->second, client_key) : options_.curve_keys.empty();
    if (shown) {
      job.set_batch_id(finished.key.first);
      job.set_job_id(finished.key.second);
    }
    job.set_status(finished.status);
    job.set_seconds(finished.seconds);
    job.set_seconds_ago(SecondsSince(finished.at, now));
  }
  return out;
}

v1::BatchStatus BrokerCore::DescribeBatch(const std::string& batch_id, const Batch& batch,
                                          const std::string& client_key, TimePoint now) const {
  v1::BatchStatus out;
  const bool shown = ShownTo(batch, client_key);
  out.set_hidden(!shown);
  if (shown) {
    out.set_batch_id(batch_id);
    out.set_client_id(batch.client_id);
  }
  const std::uint64_t queued = batch.queued;
  const std::uint64_t running = batch.running;
  out.set_queued(Count(queued));
  out.set_running(Count(running));
  out.set_done(Count(batch.done));
  out.set_failed(Count(batch.failed));
  out.set_expected(Count(batch.expected));
  out.set_age_seconds(SecondsSince(batch.opened_at, now));
  const double rate = batch.finished.PerSecond(now);
  out.set_jobs_per_second(rate);
  // What is left: the batch's announced size less what finished, or else what the broker holds of it.
  const std::uint64_t finished = batch.done + batch.failed;
  const std::uint64_t left = batch.expected > 0 ? (batch.expected > finished ? batch.expected - finished : 0)
                                                : queued + running;
  out.set_seconds_left(left == 0 ? 0.0 : rate > 0 ? static_cast<double>(left) / rate : -1.0);
  if (shown) {
    for (const Failure& failure : batch.failures) {
      v1::FailureStatus& entry = *out.add_recent_failures();
      entry.set_job_id(failure.job_id);
      entry.set_status(failure.status);
      entry.set_message(failure.message);
      entry.set_worker_id(failure.worker_id);
      entry.set_seconds_ago(SecondsSince(failure.at, now));
    }
  }
  return out;
}

}  // namespace orcs::broker
