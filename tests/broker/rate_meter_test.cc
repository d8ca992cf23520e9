// RateMeter: events per second over the last minute from per-second buckets, with a made-up clock.
#include "broker/rate_meter.h"

#include <gtest/gtest.h>

namespace orcs::broker {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

const RateMeter::Clock::time_point kStart = RateMeter::Clock::time_point{} + std::chrono::hours(2);

TEST(RateMeterTest, NothingHappenedIsZero) { EXPECT_EQ(RateMeter().PerSecond(kStart), 0.0); }

TEST(RateMeterTest, EarlyEventsAreAveragedSinceTheFirstButOverAtLeastOneSecond) {
  RateMeter meter;
  meter.Add(kStart, 3);
  EXPECT_DOUBLE_EQ(meter.PerSecond(kStart), 3.0);  // not 3 / 0
  meter.Add(kStart + seconds(3), 3);
  EXPECT_DOUBLE_EQ(meter.PerSecond(kStart + seconds(4)), 6.0 / 4.0);
}

TEST(RateMeterTest, ASteadyStreamReadsItsRateOverTheLastMinute) {
  RateMeter meter;
  for (int tenth = 0; tenth < 1200; ++tenth) meter.Add(kStart + milliseconds(100 * tenth));  // 10/s for 120 s
  EXPECT_NEAR(meter.PerSecond(kStart + seconds(120)), 10.0, 10.0 / RateMeter::kWindowSeconds);
}

TEST(RateMeterTest, EventsOlderThanTheWindowNoLongerCount) {
  RateMeter meter;
  meter.Add(kStart, 600);
  meter.Add(kStart + seconds(90), 60);
  EXPECT_DOUBLE_EQ(meter.PerSecond(kStart + seconds(90)), 1.0);  // 60 over the last 60 s; the 600 have left
  EXPECT_EQ(meter.PerSecond(kStart + seconds(200)), 0.0);
}

}  // namespace
}  // namespace orcs::broker
