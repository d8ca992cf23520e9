// One batch from submission to the last result: submits the planned jobs through a BatchClient, writes each
// result as it arrives, shows progress, and sums up. Shared by run, submit and sweep.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "clients/runtime/batch_client.h"
#include "clients/runtime/batch_input.h"
#include "clients/runtime/progress_display.h"
#include "clients/runtime/results_writer.h"

namespace orcs::runtime {

/// How a batch went.
struct BatchSummary {
  std::size_t jobs = 0;        ///< jobs submitted
  std::size_t ok = 0;          ///< results with status ok
  std::size_t failed = 0;      ///< results with any other status
  std::size_t earlier = 0;     ///< of ok + failed, results an interrupted run wrote before (--resume)
  bool interrupted = false;    ///< stopped (signal) before every result arrived
  double seconds = 0.0;        ///< wall clock from submission to the last result
  double best_fitness = 0.0;   ///< highest fitness among ok results (when ok > 0)
  std::string best_job;        ///< its job id
  std::map<std::string, std::size_t> failures;  ///< status name → count, for the failed ones
  std::vector<v1::Result> results;  ///< every result, in arrival order, logs and recordings stripped (kept when asked)

  /// Jobs run by this session per second (earlier results are not this session's).
  double jobs_per_second() const {
    return seconds > 0 ? static_cast<double>(ok + failed - earlier) / seconds : 0.0;
  }
  /// Exit code: 0 every job ran ok, 1 some failed or the batch was interrupted.
  int exit_code() const { return failed == 0 && !interrupted ? 0 : 1; }
};

/// How many jobs a session keeps outstanding (submitted, result not yet written) at most, by default.
constexpr std::size_t kDefaultWindowJobs = 10000;
/// How many bytes of jobs (serialised; nearly all of it each job's copy of its scenario) it keeps outstanding at
/// most, by default (one job more when a job alone is larger).
constexpr std::size_t kDefaultWindowBytes = std::size_t{64} << 20;

struct SessionOptions {
  const std::atomic<bool>* stop = nullptr;  ///< set (e.g. by SIGINT) to stop waiting and keep what arrived
  bool keep_results = false;                ///< keep every result in BatchSummary::results (sweep reports)
  /// The window (docs/batch.md, "Large batches"): at most this many jobs outstanding at once, ≥ 1.
  std::size_t window_jobs = kDefaultWindowJobs;
  /// ... and at most about this many bytes of them (the window always holds at least one job), ≥ 1.
  std::size_t window_bytes = kDefaultWindowBytes;
  /// Asks the broker what it is doing (net::StatusClient); nullopt when it did not answer. Set: while no
  /// result has come for `no_worker_hint_after`, the session asks (then again every as long) and says so when no
  /// worker is connected, and again when one joins; it keeps waiting either way. Null: never asks.
  std::function<std::optional<v1::Status>()> broker_status;
  std::chrono::milliseconds no_worker_hint_after{5000};
  /// Results an interrupted run of the batch already wrote (`--resume`): counted in the summary (and kept in it
  /// when keep_results) as if they had arrived first; their jobs are not in the source.
  std::vector<v1::Result> earlier_results;
};

/// Streams the jobs of `source` through the client: makes them in index order only as the window has room,
/// submits them (first the whole window, then a top-up each time a quarter of it has room), writes each result
/// as it arrives and forgets the job, so the client's and the broker's memory follow the window, not the batch.
/// Waits for all results (or `stop`) and returns the summary. Throws BatchClientError when the broker is
/// unreachable or lost for good, InputError when output cannot be written.
BatchSummary RunSession(BatchClient& client, const JobSource& source, ResultsWriter& writer,
                        ProgressDisplay& progress, const SessionOptions& options);

/// The same for jobs planned beforehand.
BatchSummary RunSession(BatchClient& client, const std::vector<PlannedJob>& jobs, ResultsWriter& writer,
                        ProgressDisplay& progress, const SessionOptions& options);

/// The closing lines: jobs ok/failed (by status), best fitness and job, jobs per second, where the results are.
std::string SummaryText(const BatchSummary& summary, const std::string& results_path);

}  // namespace orcs::runtime
