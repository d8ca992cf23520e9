#include "clients/runtime/progress_display.h"

#include <cmath>
#include <cstdio>

namespace orcs::runtime {
namespace {

constexpr int kBarWidth = 30;
constexpr std::chrono::milliseconds kTerminalInterval{100};

std::string Fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

}  // namespace

std::string FormatDuration(double seconds) {
  const long long s = std::llround(std::max(0.0, seconds));
  if (s < 60) return std::to_string(s) + " s";
  if (s < 3600) return std::to_string(s / 60) + " min " + std::to_string(s % 60) + " s";
  return std::to_string(s / 3600) + " h " + std::to_string(s % 3600 / 60) + " min";
}

ProgressDisplay::ProgressDisplay(std::ostream& out, std::size_t total, bool terminal, Clock::time_point start,
                                 std::chrono::milliseconds plain_interval)
    : out_(out), total_(total), terminal_(terminal), start_(start), interval_(plain_interval), last_drawn_(start) {}

double ProgressDisplay::Rate(std::size_t done, Clock::time_point now) const {
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::size_t since = done > earlier_ ? done - earlier_ : 0;
  return since > 0 && elapsed > 0 ? static_cast<double>(since) / elapsed : 0.0;
}

nlohmann::json ProgressDisplay::StatusJson(std::size_t ok, std::size_t failed, Clock::time_point now) const {
  const std::size_t done = ok + failed;
  const double rate = Rate(done, now);
  std::string label = label_;
  while (!label.empty() && (label.back() == ' ' || label.back() == ':')) label.pop_back();
  return {{"label", label},
          {"done", done},
          {"ok", ok},
          {"failed", failed},
          {"total", total_},
          {"jobs_per_second", rate},
          {"eta_seconds", rate > 0 && done < total_ ? nlohmann::json(static_cast<double>(total_ - done) / rate)
                                                     : nlohmann::json(nullptr)}};
}

std::string ProgressDisplay::StatusText(std::size_t ok, std::size_t failed, Clock::time_point now) const {
  const std::size_t done = ok + failed;
  std::string text = label_ + std::to_string(done) + "/" + std::to_string(total_) + " jobs (ok " + std::to_string(ok) +
                     ", failed " + std::to_string(failed) + ")";
  if (const double rate = Rate(done, now); rate > 0) {
    text += ", " + Fixed(rate, rate < 10 ? 2 : 1) + " jobs/s";
    if (done < total_) text += ", ETA " + FormatDuration(static_cast<double>(total_ - done) / rate);
  }
  return text + detail_;
}

void ProgressDisplay::Update(std::size_t ok, std::size_t failed, Clock::time_point now) {
  if (file_ != nullptr && file_->Due(now)) {
    file_->Merge(StatusJson(ok, failed, now));
    file_->Update(now, true);
  }
  const auto interval = terminal_ ? kTerminalInterval : interval_;
  if (drawn_ && now - last_drawn_ < interval) return;
  Draw(ok, failed, now);
}

void ProgressDisplay::Notice(const std::string& line) {
  if (terminal_ && drawn_) out_ << "\r\x1b[K";
  out_ << line << '\n' << std::flush;
  drawn_ = false;  // the next Update() draws the bar again
}

void ProgressDisplay::Finish(std::size_t ok, std::size_t failed, Clock::time_point now) {
  if (file_ != nullptr) {
    file_->Merge(StatusJson(ok, failed, now));
    file_->Update(now, true);
  }
  Draw(ok, failed, now);
  if (terminal_) out_ << '\n';
  out_ << std::flush;
}

void ProgressDisplay::Draw(std::size_t ok, std::size_t failed, Clock::time_point now) {
  drawn_ = true;
  last_drawn_ = now;
  if (!terminal_) {
    out_ << StatusText(ok, failed, now) << '\n' << std::flush;
    return;
  }
  const std::size_t done = ok + failed;
  const int filled = total_ == 0 ? kBarWidth : static_cast<int>(kBarWidth * done / total_);
  out_ << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
       << std::string(static_cast<std::size_t>(kBarWidth - filled), '.') << "] " << StatusText(ok, failed, now)
       << "\x1b[K" << std::flush;  // erase what a longer previous line left
}

}  // namespace orcs::runtime
