// Runs batches of jobs through the broker and hands each caller its own results, in order: the evaluation back
// end of optimisers (orcs-gap's fits, orcs-batch evolve). Several fits may run at once, each on its own thread,
// each calling Run() with one generation of jobs; they share one BatchClient, so every generation of every fit is
// in the broker's queue together and the workers (one machine or a cluster) stay busy. Whoever waits reads the
// broker's results for everyone.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "clients/runtime/batch_client.h"
#include "clients/runtime/job_evaluator.h"
#include "clients/runtime/local_cluster.h"

namespace orcs::runtime {

/// Where the jobs go: a running broker, or a local one with N worker processes.
struct RunnerOptions {
  std::string broker;          ///< client endpoint of a running broker; "" = start a local cluster
  int workers = 0;             ///< local worker processes; ≤ 0 = one per core
  std::string worker_program;  ///< orcs-worker for the local cluster ("" = beside this program)
  std::string log_path;        ///< the local cluster's log file ("" = /dev/null)
  std::string curve_keys;      ///< CURVE key folder for the client and the local cluster (docs/security.md; "" = none)
  std::chrono::milliseconds heartbeat_interval{1000};  ///< the client's and the local cluster's heartbeat
  /// Set (Ctrl-C: clients/runtime/interrupt.h): Run() stops waiting within 200 ms and throws Interrupted, in every
  /// thread that waits. Null: it waits for every result.
  const std::atomic<bool>* stop = nullptr;
};

class JobRunner : public JobEvaluator {
 public:
  /// Starts the local cluster (when no broker is given) and the client. Throws std::runtime_error when the
  /// cluster cannot start.
  explicit JobRunner(const RunnerOptions& options);
  ~JobRunner() override;
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  /// Runs `jobs` (job ids are assigned here) and returns their results in the same order. Thread-safe. Throws
  /// BatchClientError when the broker is unreachable or lost, Interrupted once `stop` is set.
  std::vector<v1::Result> Run(std::vector<v1::Job> jobs) override;
  /// The same, calling `on_result` (on the calling thread) with each of these jobs' results as it comes in: for
  /// progress within a generation.
  std::vector<v1::Result> Run(std::vector<v1::Job> jobs, const std::function<void(const v1::Result&)>& on_result);

  /// Jobs run so far.
  std::uint64_t jobs_run() const override;
  /// The number of local workers started (0 with an external broker).
  int local_workers() const { return local_workers_; }

 private:
  /// Waits for one result from the broker and files it; false on timeout.
  void ReadOneResult(std::unique_lock<std::mutex>& lock);

  const std::atomic<bool>* stop_ = nullptr;
  int local_workers_ = 0;
  std::unique_ptr<LocalCluster> cluster_;
  std::unique_ptr<BatchClient> client_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::string, v1::Result> results_;  ///< arrived, not yet collected by their caller
  bool reading_ = false;                       ///< one caller is inside client_->Next()
  std::uint64_t next_id_ = 0;
  std::uint64_t jobs_run_ = 0;
};

}  // namespace orcs::runtime
