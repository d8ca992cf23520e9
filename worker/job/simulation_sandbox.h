// Crash isolation for orcs-worker (issue 7, part 3): every job runs in a separate, long-lived simulation process,
// so that a segfault or an abort inside the physics engine kills that process and not the worker with its broker
// connection. The process is the worker's own binary in a hidden mode (`orcs-worker --sandbox-child`,
// worker/job/sandbox_child.h), started with posix_spawn — not fork(), which is unsafe in a process with ZeroMQ's
// threads — and connected by a socket pair on its descriptor 3. A job goes down as one message and its result
// comes back as one (FrameChannel), so results are the same bits as when run in-process.
//
// When the process dies while running a job, the job's result is CRASHED with a message naming the signal or exit
// code, and the next job starts a fresh process. When a job has a time limit and its process does not answer
// within the limit plus a grace (the simulation's own clock check failed: a hang inside the engine), the process
// is killed and the result is TIMEOUT.
//
// Each simulation process also runs under resource limits (docs/reliability.md "Hostile and careless input"): its
// address space is bounded (SandboxLimits::memory_bytes, `orcs-worker --memory-limit`), so that a job that allocates
// without end fails alone with CRASHED "out of memory ..." instead of taking the node's memory; and before each job
// it bounds its own CPU time to the job's time limit plus the grace (RLIMIT_CPU), so that a spinning simulation ends
// with TIMEOUT even when nobody watches it (the worker stopped with SIGSTOP, say).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"

namespace orcs::worker {

/// Resource limits of each simulation process.
struct SandboxLimits {
  /// Its address space (RLIMIT_AS), bytes; 0 = no limit. Allocations past it fail: the job is CRASHED.
  std::uint64_t memory_bytes = 0;
};

/// How a running job can be stopped from outside: `fd` becomes readable (e.g. WorkerConnection::revoked_fd()) and
/// `stop()` then says whether this job is the one to stop. Default: never.
struct RunStop {
  int fd = -1;                  ///< polled beside the simulation process; -1 = nothing to watch
  std::function<bool()> stop;   ///< asked when `fd` is readable; true = kill the process and return at once
};

/// The parent's side: runs jobs in the simulation process, one at a time. Not thread-safe; the thread that
/// constructs it must outlive the simulation process (which dies with that thread, PR_SET_PDEATHSIG).
class SimulationSandbox {
 public:
  /// `child_argv`: the simulation process's program and arguments, e.g. {"/proc/self/exe", "--sandbox-child"}.
  /// Starts it under `limits`; throws std::runtime_error naming the program when it cannot be started or limited.
  explicit SimulationSandbox(std::vector<std::string> child_argv, SandboxLimits limits = {});
  /// Kills the simulation process (it holds no state worth keeping) and reaps it.
  ~SimulationSandbox();
  SimulationSandbox(const SimulationSandbox&) = delete;
  SimulationSandbox& operator=(const SimulationSandbox&) = delete;

  /// Runs `job` in the simulation process (starting a new one when the last one died) and returns its result;
  /// CRASHED, TIMEOUT (see the top of this file) or INTERNAL_ERROR (no process could be started) otherwise.
  /// When `stop` fires (the broker revoked the job) the process is killed at once and the result is INTERNAL_ERROR
  /// "stopped: ..." (nobody reads it: the caller drops it). Never throws.
  v1::Result Run(const v1::Job& job, const RunStop& stop = {});

  /// The simulation process's pid; -1 when none is running (it died and the next Run starts one).
  pid_t child_pid() const { return pid_; }
  /// Simulation processes started so far: 1 + those started after a death.
  int processes_started() const { return processes_started_; }

  /// How long past a job's time limit its process may stay silent before it is killed: 1 s + 25 % of the limit.
  static std::chrono::steady_clock::duration Grace(double time_limit_seconds);

 private:
  void Start();
  // Applies limits_.memory_bytes to the process just started; kills it and throws when that fails.
  void LimitMemory();
  // Waits until the process has something to say, `stop` fires (true) or `deadline` passes.
  bool StoppedBeforeAnswer(const RunStop& stop, std::chrono::steady_clock::time_point deadline);
  // Whether a process is running and waiting for a job (its end of the channel is open and silent).
  bool Idle() const;
  // Kills the process (if still running) and reaps it; returns its wait status.
  int Stop();
  // Reaps a process that closed its channel: waits for it to end, killing it if it lingers; the wait status.
  int Reap();
  void CloseChannel();

  const std::vector<std::string> child_argv_;
  const SandboxLimits limits_;
  pid_t pid_ = -1;
  int fd_ = -1;  ///< the parent's end of the socket pair
  int processes_started_ = 0;
  std::string out_;  ///< reused: the serialised job
  std::string in_;   ///< reused: the serialised result
};

/// The CPU time, seconds, a simulation process may spend on a job with this time limit (0 = none): the limit plus
/// SimulationSandbox::Grace, rounded up, plus 1 s; 0 (no CPU limit) when the job has no watched limit.
std::uint64_t CpuSecondsFor(double time_limit_seconds);

/// "SIGSEGV (Segmentation fault)" for a signal number; "signal N" for one without a name.
std::string SignalName(int signal);

}  // namespace orcs::worker
