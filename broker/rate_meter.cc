#include "broker/rate_meter.h"

#include <algorithm>

namespace orcs::broker {

std::int64_t RateMeter::SecondOf(Clock::time_point time) const {
  return std::chrono::duration_cast<std::chrono::seconds>(time - *first_).count();
}

void RateMeter::Add(Clock::time_point now, std::uint64_t count) {
  if (!first_) first_ = now;
  const std::int64_t second = std::max<std::int64_t>(SecondOf(now), 0);
  const std::size_t bucket = static_cast<std::size_t>(second % kWindowSeconds);
  if (second_[bucket] != second) {  // the bucket held a second that has left the window: start it over
    second_[bucket] = second;
    counts_[bucket] = 0;
  }
  counts_[bucket] += count;
}

double RateMeter::PerSecond(Clock::time_point now) const {
  if (!first_) return 0.0;
  const std::int64_t newest = SecondOf(now);
  std::uint64_t events = 0;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    if (second_[i] > newest - kWindowSeconds && second_[i] <= newest) events += counts_[i];
  }
  const double since_first = std::chrono::duration<double>(now - *first_).count();
  const double span = std::clamp(since_first, 1.0, static_cast<double>(kWindowSeconds));
  return static_cast<double>(events) / span;
}

}  // namespace orcs::broker
