// What orcs-gap says while it works (issue 21: a diagnosis printed nothing for its whole run): a line when a fit
// starts and when it ends (its held-out gap and score, and the best model so far), and every 10 s a line with the
// time, the replays run so far and the fits under way. Plain lines, on a terminal or not: fits run at once, so
// one redrawn line could not hold them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <ostream>
#include <set>
#include <stop_token>
#include <string>
#include <thread>

#include "clients/runtime/progress_file.h"
#include "model/identify/gap_diagnosis.h"

namespace orcs::gap {

class GapProgress {
 public:
  /// Writes to `out`; `replays_run` says how many replays have run (the JobRunner's jobs); a line every `interval`.
  /// `file` (not owned; nullptr = none), progress.json for orcs-view, is written at each fit's start and end and
  /// once a second: {"replays", "fits_done", "fitting": [...], "best": {"effect", "score"}, "fits": [{"effect",
  /// "holdout_rms_deg", "score"}]}.
  /// `score_unit` names the scores' unit: "deg²" for the squared loss, "deg" for the absolute one.
  GapProgress(std::ostream& out, std::function<std::uint64_t()> replays_run,
              std::chrono::milliseconds interval = std::chrono::seconds(10), runtime::ProgressFile* file = nullptr,
              std::string score_unit = "deg²");
  /// Stops the periodic lines (ticker_, a jthread: asked to stop and joined first, being the last member).
  GapProgress(const GapProgress&) = delete;
  GapProgress& operator=(const GapProgress&) = delete;

  /// DiagnosisOptions::on_fit. Thread-safe.
  void OnFit(const std::string& model, const identify::ModelScore* finished);

  /// The periodic line now: "orcs-gap: 1 min 20 s, 2340 replays; fitting Backlash, Stribeck; best so far ...".
  std::string StatusLine();

 private:
  void Tick(std::stop_token stop);
  /// Brings the progress file up to date; with mutex_ held.
  void WriteFile(std::uint64_t replays);

  std::ostream& out_;
  const std::function<std::uint64_t()> replays_run_;
  const std::chrono::milliseconds interval_;
  const std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable_any tick_;  ///< waits out the interval; woken at once by a stop request
  std::set<std::string> running_;  ///< fits under way
  std::string best_;               ///< the best-scored candidate so far ("" = none yet)
  double best_score_ = 0;          ///< its score, in score_unit_
  const std::string score_unit_;   ///< "deg²" or "deg"
  int finished_ = 0;               ///< fits done
  runtime::ProgressFile* file_;    ///< progress.json, or nullptr
  nlohmann::json fits_ = nlohmann::json::array();  ///< the finished fits, for the file
  std::jthread ticker_;            ///< last: starts once everything above exists, stops before it goes
};

}  // namespace orcs::gap
