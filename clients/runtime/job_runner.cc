#include "clients/runtime/job_runner.h"

#include <algorithm>
#include <thread>

#include "clients/runtime/interrupt.h"

namespace orcs::runtime {

namespace {

// How long one wait lasts before the stop flag is looked at again.
constexpr std::chrono::milliseconds kPoll{200};

}  // namespace

JobRunner::JobRunner(const RunnerOptions& options) : stop_(options.stop) {
  std::string endpoint = options.broker;
  if (endpoint.empty()) {
    LocalClusterOptions cluster;
    cluster.workers = options.workers > 0 ? options.workers
                                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    cluster.worker_program =
        options.worker_program.empty() ? WorkerProgramBesideSelf() : options.worker_program;
    cluster.log_path = options.log_path;
    cluster.curve_keys = options.curve_keys;
    cluster.heartbeat_interval = options.heartbeat_interval;
    cluster_ = std::make_unique<LocalCluster>(cluster);
    local_workers_ = cluster.workers;
    endpoint = cluster_->client_endpoint();
  }
  BatchClientOptions client;
  client.endpoint = endpoint;
  client.curve_keys = options.curve_keys;
  client.heartbeat_interval = options.heartbeat_interval;
  client.log = [](std::string_view) {};  // reconnections are retried by the client; the report says what failed
  client_ = std::make_unique<BatchClient>(client);
}

JobRunner::~JobRunner() {
  client_.reset();  // tell the broker first, then stop it
  cluster_.reset();
}

std::vector<v1::Result> JobRunner::Run(std::vector<v1::Job> jobs) { return Run(std::move(jobs), {}); }

std::vector<v1::Result> JobRunner::Run(std::vector<v1::Job> jobs,
                                       const std::function<void(const v1::Result&)>& on_result) {
  std::vector<std::string> ids;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (v1::Job& job : jobs) {
      job.set_job_id("g" + std::to_string(next_id_++));
      ids.push_back(job.job_id());
    }
  }
  if (jobs.empty()) return {};
  if (stop_ != nullptr && stop_->load()) throw Interrupted();
  client_->Submit(std::move(jobs));
  std::vector<v1::Result> results(ids.size());
  std::size_t collected = 0;
  std::vector<bool> have(ids.size(), false);
  std::unique_lock<std::mutex> lock(mutex_);
  while (collected < ids.size()) {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (have[i]) continue;
      auto found = results_.find(ids[i]);
      if (found == results_.end()) continue;
      results[i] = std::move(found->second);
      results_.erase(found);
      have[i] = true;
      ++collected;
      if (on_result) {
        lock.unlock();  // the callback draws; other callers' results keep arriving meanwhile
        on_result(results[i]);
        lock.lock();
      }
    }
    if (collected == ids.size()) break;
    // The jobs of this call still in the broker's queue stay there: an interrupted command ends its batch.
    if (stop_ != nullptr && stop_->load()) throw Interrupted();
    if (reading_) {
      arrived_.wait_for(lock, kPoll);  // bounded: the reader may leave by an exception, or the stop flag be set
    } else {
      ReadOneResult(lock);
    }
  }
  jobs_run_ += ids.size();
  return results;
}

void JobRunner::ReadOneResult(std::unique_lock<std::mutex>& lock) {
  reading_ = true;
  lock.unlock();
  std::optional<v1::Result> result;
  try {
    result = client_->Next(kPoll);
  } catch (...) {
    lock.lock();
    reading_ = false;
    arrived_.notify_all();
    throw;
  }
  lock.lock();
  reading_ = false;
  if (result) results_.emplace(result->job_id(), std::move(*result));
  arrived_.notify_all();
}

std::uint64_t JobRunner::jobs_run() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return jobs_run_;
}

}  // namespace orcs::runtime
