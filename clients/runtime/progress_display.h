// How a batch shows its progress: on a terminal one bar redrawn in place ("[#####.....] 12/40 ok 12 failed 0
// 3.2 jobs/s ETA 8 s"), otherwise — a log file, CI — a plain line at most every `plain_interval`. The clock is
// passed in, so what is shown depends only on the counts and the times given.
#pragma once

#include <chrono>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "clients/runtime/progress_file.h"

namespace orcs::runtime {

class ProgressDisplay {
 public:
  using Clock = std::chrono::steady_clock;

  /// `terminal`: redraw one line with '\r'; else plain lines. Starts counting at `start`.
  ProgressDisplay(std::ostream& out, std::size_t total, bool terminal, Clock::time_point start,
                  std::chrono::milliseconds plain_interval = std::chrono::seconds(10));

  /// A result arrived; redraws when due (terminal: at most every 100 ms; plain: every plain_interval).
  void Update(std::size_t ok, std::size_t failed, Clock::time_point now);
  /// A line of its own between progress updates (e.g. "no worker is connected"): on a terminal it replaces the
  /// bar, which the next Update() draws again below it.
  void Notice(const std::string& line);
  /// Draws the final state and ends the line (terminal).
  void Finish(std::size_t ok, std::size_t failed, Clock::time_point now);

  /// Of the counts given, `earlier` were done before this run started (a resumed batch's): the rate and the
  /// time left count only the others.
  void SetEarlier(std::size_t earlier) { earlier_ = earlier; }

  /// Words before the status ("generation 3/10: ") and after it ("; best 1.2, median 0.4 so far"), "" = none.
  void SetLabel(std::string label) { label_ = std::move(label); }
  void SetDetail(std::string detail) { detail_ = std::move(detail); }

  /// Also keeps `file` (not owned; nullptr = none) up to date with StatusJson(): once a second, and at Finish().
  void WriteTo(ProgressFile* file) { file_ = file; }

  /// The status as progress.json fields: {"label", "done", "ok", "failed", "total", "jobs_per_second",
  /// "eta_seconds" (null before the first result or after the last)}.
  nlohmann::json StatusJson(std::size_t ok, std::size_t failed, Clock::time_point now) const;

  /// The status text without bar or '\r': "12/40 jobs (ok 12, failed 0), 3.2 jobs/s, ETA 8 s", between the
  /// label and the detail.
  std::string StatusText(std::size_t ok, std::size_t failed, Clock::time_point now) const;

 private:
  void Draw(std::size_t ok, std::size_t failed, Clock::time_point now);
  /// Jobs per second since the start, of the jobs done since; 0 before the first result.
  double Rate(std::size_t done, Clock::time_point now) const;

  std::ostream& out_;
  std::size_t total_;
  bool terminal_;
  Clock::time_point start_;
  std::chrono::milliseconds interval_;
  Clock::time_point last_drawn_;
  bool drawn_ = false;
  std::string label_;   ///< SetLabel()
  std::string detail_;  ///< SetDetail()
  ProgressFile* file_ = nullptr;  ///< WriteTo()
  std::size_t earlier_ = 0;       ///< SetEarlier()
};

/// "8 s", "3 min 20 s", "2 h 5 min".
std::string FormatDuration(double seconds);

}  // namespace orcs::runtime
