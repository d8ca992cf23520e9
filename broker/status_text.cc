#include "broker/status_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace orcs::broker {
namespace {

using Row = std::vector<std::string>;

// Left-aligned columns two spaces apart, widths from the widest cell.
std::string Table(const std::vector<Row>& rows) {
  std::vector<std::size_t> widths;
  for (const Row& row : rows) {
    widths.resize(std::max(widths.size(), row.size()));
    for (std::size_t i = 0; i < row.size(); ++i) widths[i] = std::max(widths[i], row[i].size());
  }
  std::ostringstream out;
  for (const Row& row : rows) {
    std::string line;
    for (std::size_t i = 0; i < row.size(); ++i) {
      line += row[i];
      if (i + 1 < row.size()) line += std::string(widths[i] - row[i].size() + 2, ' ');
    }
    out << line << "\n";
  }
  return out.str();
}

std::string Fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

// "0.4 s", "3 min 20 s", "2 h 5 min": tenths below 10 s, where heartbeats and short jobs live.
std::string HumanSeconds(double seconds) {
  if (!(seconds >= 0)) seconds = 0;
  if (seconds < 10) return Fixed(seconds, 1) + " s";
  const long whole = std::lround(seconds);
  if (whole < 60) return std::to_string(whole) + " s";
  if (whole < 3600) return std::to_string(whole / 60) + " min " + std::to_string(whole % 60) + " s";
  return std::to_string(whole / 3600) + " h " + std::to_string(whole % 3600 / 60) + " min";
}

std::string Job(const std::string& batch_id, const std::string& job_id) {
  if (job_id.empty()) return batch_id.empty() ? "-" : batch_id;
  return (batch_id.empty() ? std::string("(another key's batch)") : batch_id) + "/" + job_id;
}

std::string WorkerTable(const v1::Status& status) {
  std::vector<Row> rows = {{"WORKER", "HOST", "JOB", "FOR", "HELD", "DONE", "CRASHES", "HEARD"}};
  for (const v1::WorkerStatus& worker : status.worker_list()) {
    const bool hidden_job = worker.busy() && worker.current_job_id().empty();
    rows.push_back({worker.worker_id(), worker.host().empty() ? "-" : worker.host(),
                    worker.busy() ? (hidden_job ? "(another key's job)"
                                                : Job(worker.current_batch_id(), worker.current_job_id()))
                                  : "idle",
                    worker.busy() ? HumanSeconds(worker.current_seconds()) : "-",
                    std::to_string(worker.holding()) + "/" + std::to_string(worker.credit()),
                    std::to_string(worker.jobs_done()), std::to_string(worker.crashes()),
                    HumanSeconds(worker.last_heard_seconds()) + " ago"});
  }
  return Table(rows);
}

std::string BatchTable(const v1::Status& status) {
  std::vector<Row> rows = {{"BATCH", "CLIENT", "QUEUED", "RUNNING", "DONE", "FAILED", "OF", "JOBS/S", "LEFT"}};
  for (const v1::BatchStatus& batch : status.batch_list()) {
    rows.push_back({batch.hidden() ? "(another key's batch)" : batch.batch_id(),
                    batch.hidden() ? "-" : batch.client_id(), std::to_string(batch.queued()),
                    std::to_string(batch.running()), std::to_string(batch.done()), std::to_string(batch.failed()),
                    batch.expected() > 0 ? std::to_string(batch.expected()) : "?", Fixed(batch.jobs_per_second(), 2),
                    batch.seconds_left() < 0 ? "?" : HumanSeconds(batch.seconds_left())});
  }
  std::string text = Table(rows);
  for (const v1::BatchStatus& batch : status.batch_list()) {
    for (const v1::FailureStatus& failure : batch.recent_failures()) {
      text += "  " + batch.batch_id() + "/" + failure.job_id() + " " + v1::Result::Status_Name(failure.status()) +
              (failure.worker_id().empty() ? "" : " on " + failure.worker_id()) + ", " +
              HumanSeconds(failure.seconds_ago()) + " ago: " + failure.message() + "\n";
    }
  }
  return text;
}

}  // namespace

std::string StatusText(const v1::Status& status, const std::string& endpoint) {
  std::ostringstream out;
  out << "broker " << endpoint << ", up " << HumanSeconds(status.uptime_seconds()) << "; workers connect to "
      << status.worker_endpoint() << "\n";
  out << status.workers() << " workers (" << status.busy_workers() << " busy), " << status.queued() << " queued, "
      << status.running() << " running, " << status.done() << " done, " << status.failed() << " failed, "
      << Fixed(status.jobs_per_second(), 2) << " jobs/s over the last minute; " << status.workers_lost()
      << " workers lost, " << status.crashes() << " crashes so far\n";
  if (status.workers() == 0) {
    out << "no worker is connected: start one with `orcs-worker --connect " << status.worker_endpoint() << "`\n";
  } else {
    out << "\n" << WorkerTable(status);
  }
  if (status.batch_list_size() == 0) {
    out << "\nno batch\n";
  } else {
    out << "\n" << BatchTable(status);
  }
  return out.str();
}

}  // namespace orcs::broker
