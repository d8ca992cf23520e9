#include "clients/batch/batch_session.h"

#include <cstdio>
#include <unordered_map>

#include "model/core/text.h"
#include "worker/job/result_json.h"

namespace orcs::batch {
namespace {

using Clock = std::chrono::steady_clock;

// How long one wait for a result lasts before the stop flag is looked at again.
constexpr std::chrono::milliseconds kPoll{200};

void Count(const v1::Result& result, BatchSummary& summary) {
  if (result.status() != v1::Result::OK) {
    ++summary.failed;
    ++summary.failures[std::string(worker::StatusName(result.status()))];
    return;
  }
  if (summary.ok == 0 || result.fitness() > summary.best_fitness) {
    summary.best_fitness = result.fitness();
    summary.best_job = result.job_id();
  }
  ++summary.ok;
}

}  // namespace

BatchSummary RunSession(broker::BatchClient& client, const std::vector<PlannedJob>& jobs, ResultsWriter& writer,
                        ProgressDisplay& progress, const SessionOptions& options) {
  BatchSummary summary;
  summary.jobs = jobs.size();
  std::unordered_map<std::string, const nlohmann::ordered_json*> extras;
  std::vector<v1::Job> submission;
  submission.reserve(jobs.size());
  for (const PlannedJob& planned : jobs) {
    extras[planned.job.job_id()] = &planned.extra;
    submission.push_back(planned.job);
  }
  const Clock::time_point start = Clock::now();
  client.Submit(std::move(submission));
  while (summary.ok + summary.failed < summary.jobs) {
    if (options.stop != nullptr && options.stop->load()) {
      summary.interrupted = true;
      break;
    }
    std::optional<v1::Result> result = client.Next(kPoll);
    if (!result) continue;
    writer.Write(*result, *extras.at(result->job_id()));
    Count(*result, summary);
    progress.Update(summary.ok, summary.failed, Clock::now());
    if (options.keep_results) {
      result->clear_logs();
      result->clear_recording();  // written to recordings/ already; a sweep's table needs only the numbers
      summary.results.push_back(std::move(*result));
    }
  }
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  progress.Finish(summary.ok, summary.failed, Clock::now());
  return summary;
}

std::string SummaryText(const BatchSummary& summary, const std::string& results_path) {
  char rate[64];
  std::snprintf(rate, sizeof rate, "%.2f jobs/s in %.2f s", summary.jobs_per_second(), summary.seconds);
  std::string text = "orcs-batch: " + std::to_string(summary.ok + summary.failed) + " of " +
                     std::to_string(summary.jobs) + " jobs ran: " + std::to_string(summary.ok) + " ok, " +
                     std::to_string(summary.failed) + " failed";
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

}  // namespace orcs::batch
