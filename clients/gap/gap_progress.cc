#include "clients/gap/gap_progress.h"

#include <cstdio>

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
                         std::chrono::milliseconds interval)
    : out_(out), replays_run_(std::move(replays_run)), interval_(interval), start_(std::chrono::steady_clock::now()) {
  ticker_ = std::thread([this] { Tick(); });
}

GapProgress::~GapProgress() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_.notify_all();
  ticker_.join();
}

void GapProgress::Tick() {
  std::unique_lock lock(mutex_);
  while (!stop_.wait_for(lock, interval_, [this] { return stopping_; })) {
    lock.unlock();
    const std::string line = StatusLine();
    lock.lock();
    out_ << line << std::endl;
  }
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
  if (!best_.empty()) line += "; best so far " + best_ + " (score " + Fixed(best_score_, "%.4g") + " deg²)";
  return line;
}

void GapProgress::OnFit(const std::string& model, const identify::ModelScore* finished) {
  std::lock_guard lock(mutex_);
  if (finished == nullptr) {
    running_.insert(model);
    out_ << "orcs-gap: fitting " << (model == "refit" ? "the model's own parameters (refit)" : model) << std::endl;
    return;
  }
  running_.erase(model);
  ++finished_;
  std::string line = "orcs-gap: " + model + " fitted: held-out gap " + Fixed(finished->holdout_rms, "%.3f") +
                     "° RMS, score " + Fixed(finished->score, "%.4g") + " deg²";
  if (model == "refit") {
    line += " (nothing missing; an effect must score below half of it to be named)";
  } else if (best_.empty() || finished->score < best_score_) {
    best_ = model;
    best_score_ = finished->score;
    line += "; best so far";
  }
  out_ << line << std::endl;
}

}  // namespace orcs::gap
