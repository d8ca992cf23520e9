// The progress display: what it shows for given counts and times (the clock is passed in).
#include "clients/runtime/progress_display.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

namespace orcs::runtime {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using ::testing::HasSubstr;
using ::testing::Not;
using Clock = ProgressDisplay::Clock;

TEST(ProgressDisplayTest, StatusTextHasCountsRateAndEta) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 40, false, start);
  EXPECT_EQ(progress.StatusText(0, 0, start), "0/40 jobs (ok 0, failed 0)");
  EXPECT_EQ(progress.StatusText(9, 1, start + seconds(5)), "10/40 jobs (ok 9, failed 1), 2.00 jobs/s, ETA 15 s");
  EXPECT_EQ(progress.StatusText(40, 0, start + seconds(2)), "40/40 jobs (ok 40, failed 0), 20.0 jobs/s");
}

// A resumed batch: 10 of its 40 jobs were done before; the rate and the time left count this run's jobs only.
TEST(ProgressDisplayTest, AResumedBatchCountsItsEarlierJobsButNotInItsRate) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 40, false, start);
  progress.SetEarlier(10);
  EXPECT_EQ(progress.StatusText(10, 0, start + seconds(1)), "10/40 jobs (ok 10, failed 0)");
  EXPECT_EQ(progress.StatusText(20, 0, start + seconds(5)), "20/40 jobs (ok 20, failed 0), 2.00 jobs/s, ETA 10 s");
}

TEST(ProgressDisplayTest, PlainOutputPrintsALineAtMostEveryInterval) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 10, false, start, seconds(10));
  progress.Update(1, 0, start + seconds(1));   // first: drawn
  progress.Update(2, 0, start + seconds(5));   // too soon
  progress.Update(3, 0, start + seconds(12));  // due
  progress.Finish(10, 0, start + seconds(20));
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3) << text;
  EXPECT_THAT(text, HasSubstr("1/10 jobs"));
  EXPECT_THAT(text, Not(HasSubstr("2/10 jobs")));
  EXPECT_THAT(text, HasSubstr("3/10 jobs"));
  EXPECT_THAT(text, HasSubstr("10/10 jobs"));
  EXPECT_THAT(text, Not(HasSubstr("\r")));
}

TEST(ProgressDisplayTest, TerminalOutputRedrawsOneBarInPlace) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 4, true, start);
  progress.Update(1, 0, start + milliseconds(500));
  progress.Update(2, 0, start + milliseconds(550));  // within 100 ms: not redrawn
  progress.Update(3, 0, start + milliseconds(700));
  progress.Finish(4, 0, start + seconds(1));
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\r'), 3) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_THAT(text, HasSubstr("[" + std::string(30, '#') + "] 4/4 jobs"));
  EXPECT_THAT(text, HasSubstr("[" + std::string(7, '#') + std::string(23, '.') + "] 1/4 jobs"));
}

TEST(ProgressDisplayTest, FormatsDurations) {
  EXPECT_EQ(FormatDuration(8.4), "8 s");
  EXPECT_EQ(FormatDuration(200), "3 min 20 s");
  EXPECT_EQ(FormatDuration(7500), "2 h 5 min");
  EXPECT_EQ(FormatDuration(-3), "0 s");
}

TEST(ProgressDisplayTest, ALabelAndADetailFrameTheStatus) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 6, false, start);
  progress.SetLabel("generation 3/10: ");
  progress.SetDetail("; best 1.2 in this generation so far");
  EXPECT_EQ(progress.StatusText(2, 0, start + seconds(1)),
            "generation 3/10: 2/6 jobs (ok 2, failed 0), 2.00 jobs/s, ETA 2 s; best 1.2 in this generation so far");
}

TEST(ProgressDisplayTest, ANoticeOnATerminalReplacesTheBarWhichTheNextUpdateDrawsAgain) {
  std::ostringstream out;
  const Clock::time_point start{};
  ProgressDisplay progress(out, 10, true, start);
  progress.Update(1, 0, start + seconds(1));
  progress.Notice("orcs-batch: no worker is connected");
  progress.Update(2, 0, start + seconds(1));  // at once: the bar was erased, so it is due
  const std::string text = out.str();
  const std::size_t notice = text.find("\r\x1b[Korcs-batch: no worker is connected\n");
  ASSERT_NE(notice, std::string::npos) << text;
  EXPECT_LT(text.find("1/10 jobs"), notice);
  EXPECT_GT(text.find("2/10 jobs"), notice);
}

}  // namespace
}  // namespace orcs::runtime
