// The one-machine default of `orcs-batch run` (docs/architecture.md, "One machine"): a broker embedded in this process on
// loopback ephemeral ports, and N orcs-worker processes connected to it. Workers are processes, not threads, so
// that they scale like on a cluster and one that crashes takes nothing else with it. Each is the leader of its own
// process group, so that a terminal's Ctrl-C, which goes to this program's group, does not end them under the
// batch (issue 47): this program stops them. They die with the thread that made the cluster (PR_SET_PDEATHSIG), a
// second Ctrl-C kills them (clients/runtime/interrupt.h), and the destructor stops them and the broker.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "broker/broker.h"

namespace orcs::runtime {

struct LocalClusterOptions {
  int workers = 1;                  ///< orcs-worker processes to start, ≥ 1
  std::string worker_program;       ///< path of orcs-worker
  std::string log_path;             ///< file the broker's and workers' log lines are appended to ("" = /dev/null)
  std::chrono::milliseconds heartbeat_interval{1000};  ///< broker's and workers' heartbeat
  /// CURVE keys for the broker and the workers (docs/security.md): broker.key/.pub, allowed_workers/,
  /// allowed_clients/, worker.key/.pub ("" = plain TCP)
  std::string curve_keys;
};

class LocalCluster {
 public:
  /// Starts the broker and the workers. Throws std::runtime_error when the broker cannot bind, the worker
  /// program is missing, or a process cannot be started; net::CurveKeyError for a missing or malformed key.
  explicit LocalCluster(LocalClusterOptions options);
  /// Stops the workers (SIGTERM; SIGKILL to the group of any still running after a grace period: 3 s, 1 s once
  /// interrupted) and the broker.
  ~LocalCluster();
  LocalCluster(const LocalCluster&) = delete;
  LocalCluster& operator=(const LocalCluster&) = delete;

  /// Where clients connect, e.g. "tcp://127.0.0.1:41234".
  const std::string& client_endpoint() const { return broker_->client_endpoint(); }
  /// The broker's counters (workers registered, jobs requeued, ...).
  broker::BrokerStats stats() const { return broker_->stats(); }
  /// How many of the started workers have exited so far (reaped without waiting).
  int workers_exited();

 private:
  pid_t StartWorker(int index) const;
  void StopWorkers();

  LocalClusterOptions options_;
  int log_fd_ = -1;                      ///< the log file, shared by the broker thread and the workers' stderr
  std::mutex log_mutex_;                 ///< serialises the broker's log lines
  std::unique_ptr<broker::Broker> broker_;
  std::thread broker_thread_;
  std::vector<pid_t> workers_;           ///< started and not yet reaped (-1 once reaped)
};

/// The orcs-worker next to the running program (/proc/self/exe's folder), or "" when there is none.
std::string WorkerProgramBesideSelf();

}  // namespace orcs::runtime
