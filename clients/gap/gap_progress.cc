#include "clients/gap/gap_progress.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace orcs::gap {
namespace {

std::string Fixed(double value, const char* format) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string Elapsed(double seconds) {
  const long s = static_cast<long>(seconds);
  return s < 60 ? std::to_string(s) + " s" : std::to_string(s / 60) + " min " + std::to_string(s % 60) + " s";
}

}  // namespace

GapProgress::GapProgress(std::ostream& out, std::function<std::uint64_t()> replays_run,
                         std::chrono::milliseconds interval, runtime::ProgressFile* file, std::string score_unit)
    : out_(out),
      replays_run_(std::move(replays_run)),
      interval_(interval),
      start_(std::chrono::steady_clock::now()),
      score_unit_(std::move(score_unit)),
      file_(file) {
  ticker_ = std::jthread([this](std::stop_token stop) { Tick(stop); });
}

// Wakes once a second for the progress file, and prints the status line every `interval_`.
void GapProgress::Tick(std::stop_token stop) {
  const auto wake = std::min<std::chrono::milliseconds>(interval_, std::chrono::seconds(1));
  auto next_line = std::chrono::steady_clock::now() + interval_;
  std::unique_lock lock(mutex_);
  while (!tick_.wait_for(lock, stop, wake, [&stop] { return stop.stop_requested(); })) {
    lock.unlock();
    const std::uint64_t replays = replays_run_();
    const bool line_due = std::chrono::steady_clock::now() >= next_line;
    const std::string line = line_due ? StatusLine() : "";
    lock.lock();
    if (line_due) {
      out_ << line << std::endl;
      next_line += interval_;
    }
    WriteFile(replays);
  }
}

void GapProgress::WriteFile(std::uint64_t replays) {
  if (file_ == nullptr) return;
  file_->Set("replays", replays);
  file_->Set("fits_done", finished_);
  file_->Set("fitting", nlohmann::json(std::vector<std::string>(running_.begin(), running_.end())));
  file_->Set("best", best_.empty() ? nlohmann::json(nullptr) : nlohmann::json{{"effect", best_}, {"score", best_score_}});
  file_->Set("fits", fits_);
  file_->Update(std::chrono::steady_clock::now(), true);
}

std::string GapProgress::StatusLine() {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::uint64_t replays = replays_run_();
  std::lock_guard lock(mutex_);
  std::string line = "orcs-gap: " + Elapsed(seconds) + ", " + std::to_string(replays) + " replays, " +
                     std::to_string(finished_) + " fits done";
  if (!running_.empty()) {
    line += "; fitting";
    const char* separator = " ";
    for (const std::string& model : running_) {
      line += separator + model;
      separator = ", ";
    }
  }
  if (!best_.empty()) line += "; best so far " + best_ + " (score " + Fixed(best_score_, "%.4g") + " " + score_unit_ + ")";
  return line;
}

void GapProgress::OnFit(const std::string& model, const identify::ModelScore* finished) {
  const std::uint64_t replays = replays_run_();  // before the lock: the runner has its own
  std::lock_guard lock(mutex_);
  if (finished == nullptr) {
    running_.insert(model);
    out_ << "orcs-gap: fitting " << (model == "refit" ? "the model's own parameters (refit)" : model) << std::endl;
    WriteFile(replays);
    return;
  }
  running_.erase(model);
  ++finished_;
  fits_.push_back({{"effect", model}, {"holdout_rms_deg", finished->holdout_rms}, {"score", finished->score}});
  std::string line = "orcs-gap: " + model + " fitted: held-out gap " + Fixed(finished->holdout_rms, "%.3f") +
                     "° RMS, score " + Fixed(finished->score, "%.4g") + " " + score_unit_;
  if (model == "refit") {
    line += " (nothing missing; an effect must score below half of it to be named)";
  } else if (best_.empty() || finished->score < best_score_) {
    best_ = model;
    best_score_ = finished->score;
    line += "; best so far";
  }
  out_ << line << std::endl;
  WriteFile(replays);
}

}  // namespace orcs::gap
