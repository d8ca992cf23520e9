// What orcs-gap says while it works: a line per fit started and finished, the best candidate so far, and the
// periodic status line (asked for directly here; its thread is given an hour, so it never speaks in the test).
#include "clients/gap/gap_progress.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <sstream>

#include "tests/support/temp_dir.h"

namespace orcs::gap {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

identify::ModelScore Score(const std::string& label, double holdout_rms, double score) {
  identify::ModelScore s;
  s.label = label;
  s.holdout_rms = holdout_rms;
  s.score = score;
  return s;
}

TEST(GapProgressTest, SaysWhichFitsRunAndWhichCandidateIsBestSoFar) {
  std::ostringstream out;
  std::atomic<std::uint64_t> replays{0};
  GapProgress progress(out, [&] { return replays.load(); }, std::chrono::hours(1));
  progress.OnFit("refit", nullptr);
  const identify::ModelScore refit = Score("refit", 9.4, 88.8);
  progress.OnFit("refit", &refit);
  progress.OnFit("Backlash", nullptr);
  progress.OnFit("TransportDelay", nullptr);
  replays = 120;
  EXPECT_EQ(progress.StatusLine().substr(0, 10), "orcs-gap: ");
  EXPECT_THAT(progress.StatusLine(), HasSubstr(", 120 replays, 1 fits done; fitting Backlash, TransportDelay"));
  const identify::ModelScore worse = Score("Backlash", 9.3, 91.2);
  progress.OnFit("Backlash", &worse);
  const identify::ModelScore better = Score("TransportDelay", 0.189, 0.0375);
  progress.OnFit("TransportDelay", &better);
  const std::string line = progress.StatusLine();
  EXPECT_THAT(line, HasSubstr("3 fits done; best so far TransportDelay (score 0.0375 deg²)"));
  EXPECT_THAT(line, Not(HasSubstr("fitting")));

  const std::string text = out.str();
  EXPECT_THAT(text, HasSubstr("orcs-gap: fitting the model's own parameters (refit)\n"));
  EXPECT_THAT(text, HasSubstr("orcs-gap: refit fitted: held-out gap 9.400° RMS, score 88.8 deg² (nothing missing"));
  EXPECT_THAT(text, HasSubstr("orcs-gap: Backlash fitted: held-out gap 9.300° RMS, score 91.2 deg²; best so far\n"));
  EXPECT_THAT(text, HasSubstr("orcs-gap: TransportDelay fitted: held-out gap 0.189° RMS, score 0.0375 deg²; best so far"));
}

// With the absolute loss (orcs-gap --loss absolute) a score is a mean absolute error in degrees, and says so.
TEST(GapProgressTest, ScoresCarryTheLosssUnit) {
  std::ostringstream out;
  GapProgress progress(out, [] { return std::uint64_t{0}; }, std::chrono::hours(1), nullptr, "deg");
  const identify::ModelScore refit = Score("refit", 2.2, 1.8);
  progress.OnFit("refit", &refit);
  const identify::ModelScore candidate = Score("Backlash", 2.0, 1.6);
  progress.OnFit("Backlash", &candidate);
  EXPECT_THAT(out.str(), HasSubstr("held-out gap 2.000° RMS, score 1.6 deg; best so far"));
  EXPECT_THAT(progress.StatusLine(), HasSubstr("best so far Backlash (score 1.6 deg)"));
  EXPECT_THAT(out.str(), Not(HasSubstr("deg²")));
}

// The same progress, for orcs-view: progress.json says what is fitted, the finished fits and the best so far.
TEST(GapProgressTest, KeepsProgressJsonUpToDateForThePage) {
  test_support::TempDir dir;
  std::ostringstream out;
  runtime::ProgressFile file(dir.path().string(), "gap");
  const auto written = [&] { return nlohmann::json::parse(dir.Read(runtime::kProgressFile)); };
  {
    GapProgress progress(out, [] { return std::uint64_t{42}; }, std::chrono::hours(1), &file);
    progress.OnFit("Backlash", nullptr);
    nlohmann::json now = written();
    EXPECT_EQ(now["fitting"], nlohmann::json::array({"Backlash"}));
    EXPECT_EQ(now["replays"], 42);
    EXPECT_EQ(now["fits_done"], 0);
    EXPECT_FALSE(now.contains("best"));
    const identify::ModelScore score = Score("Backlash", 0.5, 0.25);
    progress.OnFit("Backlash", &score);
    now = written();
    EXPECT_TRUE(now["fitting"].empty());
    EXPECT_EQ(now["fits_done"], 1);
    EXPECT_EQ(now["best"]["effect"], "Backlash");
    EXPECT_DOUBLE_EQ(now["best"]["score"].get<double>(), 0.25);
    ASSERT_EQ(now["fits"].size(), 1u);
    EXPECT_DOUBLE_EQ(now["fits"][0]["holdout_rms_deg"].get<double>(), 0.5);
    EXPECT_EQ(now["state"], "running");
  }
  file.Finish("finished");
  EXPECT_EQ(written()["state"], "finished");
}

}  // namespace
}  // namespace orcs::gap
