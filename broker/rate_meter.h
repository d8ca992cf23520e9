// Events per second over the last minute, for the broker's status (jobs/s of a batch, of the whole broker):
// per-second buckets in a fixed ring, so an event costs O(1) and a meter a fixed 1 KiB however busy it is. The
// clock is passed in, as everywhere in the broker's core.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>

namespace orcs::broker {

class RateMeter {
 public:
  using Clock = std::chrono::steady_clock;
  /// The span the rate is averaged over, s.
  static constexpr int kWindowSeconds = 60;

  /// `count` events happened at `now` (times must not go backwards by more than the window).
  void Add(Clock::time_point now, std::uint64_t count = 1);
  /// Events per second over the last kWindowSeconds before `now` — or, while the first event is younger than
  /// that, since the first event (at least over one second, so one early event is not an infinite rate). 0 when
  /// nothing happened within the window.
  double PerSecond(Clock::time_point now) const;

 private:
  /// Whole seconds since `origin_`.
  std::int64_t SecondOf(Clock::time_point time) const;

  std::optional<Clock::time_point> first_;          ///< the first event ever; also the buckets' origin
  std::array<std::uint64_t, kWindowSeconds> counts_{};  ///< events in the second second_[i]
  std::array<std::int64_t, kWindowSeconds> second_{};   ///< which second (since first_) bucket i holds
};

}  // namespace orcs::broker
