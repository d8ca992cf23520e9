#include "clients/runtime/batch_session.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

#include "model/core/text.h"
#include "proto/result_json.h"

namespace orcs::runtime {
namespace {

using Clock = std::chrono::steady_clock;

// How long one wait for a result lasts before the stop flag is looked at again.
constexpr std::chrono::milliseconds kPoll{200};

void Count(const v1::Result& result, BatchSummary& summary) {
  if (result.status() != v1::Result::OK) {
    ++summary.failed;
    ++summary.failures[std::string(proto::StatusName(result.status()))];
    return;
  }
  if (summary.ok == 0 || result.fitness() > summary.best_fitness) {
    summary.best_fitness = result.fitness();
    summary.best_job = result.job_id();
  }
  ++summary.ok;
}

// Says so when a batch waits and no worker is connected to the broker, and again when one joins (issue 21: a batch
// submitted before any worker used to sit at 0/N without a word).
class WorkerWatch {
 public:
  WorkerWatch(const SessionOptions& options, ProgressDisplay& progress, Clock::time_point start)
      : options_(options), progress_(progress), quiet_since_(start), next_check_(start) {}

  /// A result came: the batch is moving.
  void OnResult(Clock::time_point now) { quiet_since_ = now; }

  /// Asks the broker when the batch has been quiet long enough and the last question is old enough.
  void Check(Clock::time_point now) {
    if (!options_.broker_status) return;
    const auto after = options_.no_worker_hint_after;
    if (now - quiet_since_ < after || now < next_check_) return;
    next_check_ = now + after;
    const std::optional<v1::Status> status = options_.broker_status();
    if (!status) return;
    if (status->workers() == 0 && !hinted_) {
      progress_.Notice("orcs-batch: no worker is connected to the broker, so the jobs wait in its queue; start one "
                       "with `orcs-worker --connect " + status->worker_endpoint() + "` (docs/cluster.md). Still "
                       "waiting.");
      hinted_ = true;
    } else if (status->workers() > 0 && hinted_) {
      progress_.Notice("orcs-batch: " + std::to_string(status->workers()) +
                       (status->workers() == 1 ? " worker" : " workers") + " connected now; the jobs run.");
      hinted_ = false;
    }
  }

 private:
  const SessionOptions& options_;
  ProgressDisplay& progress_;
  Clock::time_point quiet_since_;  ///< the start, or the last result
  Clock::time_point next_check_;   ///< no question to the broker before this
  bool hinted_ = false;            ///< "no worker" was said and no worker has been seen since
};

}  // namespace

BatchSummary RunSession(BatchClient& client, const JobSource& source, ResultsWriter& writer,
                        ProgressDisplay& progress, const SessionOptions& options) {
  BatchSummary summary;
  summary.jobs = source.size() + options.earlier_results.size();
  summary.earlier = options.earlier_results.size();
  for (const v1::Result& earlier : options.earlier_results) {
    Count(earlier, summary);
    if (options.keep_results) summary.results.push_back(earlier);
  }
  const std::size_t window_jobs = std::max<std::size_t>(1, options.window_jobs);
  const std::size_t window_bytes = std::max<std::size_t>(1, options.window_bytes);
  // The outstanding jobs: what their results.jsonl line adds, and their size. Bounded by the window.
  struct Outstanding {
    nlohmann::ordered_json extra;
    std::size_t bytes = 0;
  };
  std::unordered_map<std::string, Outstanding> outstanding;
  std::size_t outstanding_bytes = 0;
  std::size_t next = 0;  // the next job to make
  // Fills the window when there is room for a quarter of it (or nothing is outstanding), so that each SUBMIT
  // carries many jobs and the broker's queue never runs dry while the top-up travels.
  const auto top_up = [&] {
    if (next >= source.size()) return;
    const bool room = outstanding.empty() ||
                      (window_jobs - outstanding.size() >= std::max<std::size_t>(1, window_jobs / 4) &&
                       outstanding_bytes + window_bytes / 4 <= window_bytes);
    if (!room) return;
    std::vector<v1::Job> submission;
    while (next < source.size() && outstanding.size() < window_jobs &&
           (outstanding.empty() || outstanding_bytes < window_bytes)) {
      PlannedJob planned = source.Job(next++);
      const std::size_t bytes = planned.job.ByteSizeLong();
      outstanding_bytes += bytes;
      outstanding.emplace(planned.job.job_id(), Outstanding{std::move(planned.extra), bytes});
      submission.push_back(std::move(planned.job));
    }
    if (!submission.empty()) client.Submit(std::move(submission));
  };
  const Clock::time_point start = Clock::now();
  WorkerWatch workers(options, progress, start);
  top_up();
  while (summary.ok + summary.failed < summary.jobs) {
    if (options.stop != nullptr && options.stop->load()) {
      summary.interrupted = true;
      break;
    }
    std::optional<v1::Result> result = client.Next(kPoll);
    if (!result) {
      workers.Check(Clock::now());
      continue;
    }
    workers.OnResult(Clock::now());
    const auto job = outstanding.find(result->job_id());
    if (job == outstanding.end()) {
      throw std::logic_error("a result for job '" + result->job_id() + "', which is not outstanding");
    }
    writer.Write(*result, job->second.extra);
    outstanding_bytes -= job->second.bytes;
    outstanding.erase(job);
    Count(*result, summary);
    progress.Update(summary.ok, summary.failed, Clock::now());
    if (options.keep_results) {
      result->clear_logs();
      result->clear_recording();  // written to recordings/ already; a sweep's table needs only the numbers
      summary.results.push_back(std::move(*result));
    }
    top_up();
  }
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  progress.Finish(summary.ok, summary.failed, Clock::now());
  return summary;
}

BatchSummary RunSession(BatchClient& client, const std::vector<PlannedJob>& jobs, ResultsWriter& writer,
                        ProgressDisplay& progress, const SessionOptions& options) {
  return RunSession(client, PlannedJobList(jobs), writer, progress, options);
}

std::string SummaryText(const BatchSummary& summary, const std::string& results_path) {
  char rate[64];
  std::snprintf(rate, sizeof rate, "%.2f jobs/s in %.2f s", summary.jobs_per_second(), summary.seconds);
  std::string text = "orcs-batch: " + std::to_string(summary.ok + summary.failed) + " of " +
                     std::to_string(summary.jobs) + " jobs ran: " + std::to_string(summary.ok) + " ok, " +
                     std::to_string(summary.failed) + " failed";
  if (summary.earlier > 0) text += " (" + std::to_string(summary.earlier) + " of them before the interruption)";
  if (!summary.failures.empty()) {
    text += " (";
    bool first = true;
    for (const auto& [status, count] : summary.failures) {
      text += (first ? "" : ", ") + status + " " + std::to_string(count);
      first = false;
    }
    text += ")";
  }
  text += "; " + std::string(rate);
  if (summary.interrupted) text += "; interrupted";
  text += "\n";
  if (summary.ok > 0) {
    text += "orcs-batch: best fitness " + text::FormatDouble(summary.best_fitness) + " (" + summary.best_job + ")\n";
  }
  text += "orcs-batch: results in " + results_path + "\n";
  return text;
}

}  // namespace orcs::runtime
