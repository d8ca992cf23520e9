// Issue 21 item 4: `orcs-batch run|sweep --resume DIR` completes an interrupted batch. The real orcs-batch with two
// local orcs-worker processes on 127.0.0.1 is interrupted with SIGINT once about half its results are in, then
// resumed: every job has exactly one line (so no finished job ran again — the writer appends every result it
// gets), the lines written before the interruption are kept byte for byte, and every job's numbers are the bits of
// an uninterrupted run of the same batch. A resume that contradicts the batch, or whose scenario changed, is
// refused with one line naming the option or file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;

const std::string kBatch = ORCS_BINARY_DIR "/bin/orcs-batch";

// The A-Series swinging its hips for 4 simulated seconds under two drawn parameter sets: about 0.4 s a job.
constexpr const char* kScenario = R"({
  "name": "resume-test",
  "duration": 4.0,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "genome": [10.0, 1.0, 0.0, 0.0, 10.0, 1.0, 3.0, 0.0],
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]},
  "randomisation": {"sets": 2, "default_motor_model": true}
})";

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Each job's line without what depends on the run rather than the job: which worker, how long, how many tries.
std::map<std::string, nlohmann::json> ByJob(const std::vector<std::string>& lines) {
  std::map<std::string, nlohmann::json> jobs;
  for (const std::string& line : lines) {
    nlohmann::json json = nlohmann::json::parse(line);
    for (const char* run_dependent : {"worker", "timings", "attempts"}) json.erase(run_dependent);
    jobs[json["id"].get<std::string>()] = json;
  }
  return jobs;
}

class BatchResumeTest : public ::testing::Test {
 protected:
  std::string Out(const std::string& name) { return dir_.PathOf(name); }

  // Starts `arguments` and sends SIGINT once the partial file holds `lines` lines; returns the partial's lines.
  std::vector<std::string> Interrupt(const std::vector<std::string>& arguments, const std::string& out,
                                     std::size_t lines) {
    std::vector<std::string> argv = {kBatch};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    BackgroundProcess batch(argv);
    const std::string partial = out + "/results.jsonl.partial";
    const Clock::time_point deadline = Clock::now() + milliseconds(120000);
    while (Lines(partial).size() < lines && Clock::now() < deadline) {
      if (batch.Wait(milliseconds(20)).has_value()) break;
    }
    batch.Signal(SIGINT);
    const std::optional<ProcessResult> ended = batch.Wait(milliseconds(30000));
    EXPECT_TRUE(ended.has_value());
    if (ended) {
      EXPECT_EQ(ended->exit_code, 130) << "an interrupted batch exits 130: " << ended->err;
    }
    return Lines(partial);
  }

  test_support::TempDir dir_;
};

TEST_F(BatchResumeTest, ARunInterruptedAtHalfAndResumedHasTheBitsOfAnUninterruptedRunAndRunsNoJobTwice) {
  const std::string scenario = dir_.Write("s.json", kScenario);
  const std::vector<std::string> batch = {scenario, "--jobs", "16", "--workers", "2", "--quiet"};
  std::vector<std::string> whole = {"run"};
  whole.insert(whole.end(), batch.begin(), batch.end());
  whole.insert(whole.end(), {"--out", Out("whole")});
  const ProcessResult uninterrupted = RunProcess([&] {
    std::vector<std::string> argv = {kBatch};
    argv.insert(argv.end(), whole.begin(), whole.end());
    return argv;
  }());
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;

  std::vector<std::string> cut = {"run"};
  cut.insert(cut.end(), batch.begin(), batch.end());
  cut.insert(cut.end(), {"--out", Out("cut")});
  const std::vector<std::string> before = Interrupt(cut, Out("cut"), 8);
  ASSERT_GE(before.size(), 1u);
  ASSERT_LT(before.size(), 16u) << "the batch ended before it could be interrupted";
  EXPECT_EQ(nlohmann::json::parse(dir_.Read(Out("cut") + "/progress.json"))["state"], "interrupted");

  // Refused, naming what is wrong, and nothing is touched.
  ProcessResult refused = RunProcess({kBatch, "run", "--resume", Out("cut"), "--jobs", "9"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.err, HasSubstr("--jobs: the batch in " + Out("cut") + " was started with 16, not 9"));
  refused = RunProcess({kBatch, "sweep", "--resume", Out("cut")});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.err, HasSubstr("holds a run batch; resume it with `orcs-batch run --resume"));
  refused = RunProcess({kBatch, "run", "--resume", Out("whole")});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.err, HasSubstr("the batch is complete already"));
  EXPECT_EQ(Lines(Out("cut") + "/results.jsonl.partial"), before);

  // The same command again with --resume: the same settings are accepted.
  std::vector<std::string> resume = {kBatch};
  resume.insert(resume.end(), cut.begin(), cut.end());
  resume.insert(resume.end(), {"--resume", Out("cut")});
  const ProcessResult resumed = RunProcess(resume);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr(std::to_string(before.size()) + " of 16 jobs have their result; running the other " +
                                     std::to_string(16 - before.size())));
  EXPECT_THAT(resumed.out, HasSubstr("(" + std::to_string(before.size()) + " of them before the interruption)"));
  // orcs-view's page follows the resumed run: the jobs it ran, of how many, and its end.
  const nlohmann::json progress = nlohmann::json::parse(dir_.Read(Out("cut") + "/progress.json"));
  EXPECT_EQ(progress["state"], "finished");
  EXPECT_EQ(progress["earlier"], before.size());
  EXPECT_EQ(progress["done"], 16);
  EXPECT_EQ(progress["total"], 16);

  const std::vector<std::string> after = Lines(Out("cut") + "/results.jsonl");
  ASSERT_EQ(after.size(), 16u) << "one line per job: a job that ran again would add a line";
  EXPECT_EQ(std::vector<std::string>(after.begin(), after.begin() + static_cast<long>(before.size())), before);
  const std::map<std::string, nlohmann::json> resumed_jobs = ByJob(after);
  EXPECT_EQ(resumed_jobs.size(), 16u);
  EXPECT_EQ(resumed_jobs, ByJob(Lines(Out("whole") + "/results.jsonl")));
}

TEST_F(BatchResumeTest, ASweepResumedWithOnlyResumeHasTheTableOfAnUninterruptedOne) {
  const std::string scenario = dir_.Write("s.json", kScenario);
  const std::vector<std::string> sweep = {"sweep", scenario, "--param", "/AngularMotor/PID/Proportional=10,20,30,40",
                                          "--jobs", "3", "--workers", "2", "--quiet"};
  std::vector<std::string> whole = {kBatch};
  whole.insert(whole.end(), sweep.begin(), sweep.end());
  whole.insert(whole.end(), {"--out", Out("whole")});
  const ProcessResult uninterrupted = RunProcess(whole);
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;

  std::vector<std::string> cut = sweep;
  cut.insert(cut.end(), {"--out", Out("cut")});
  const std::vector<std::string> before = Interrupt(cut, Out("cut"), 6);
  ASSERT_LT(before.size(), 12u) << "the sweep ended before it could be interrupted";

  const ProcessResult resumed = RunProcess({kBatch, "sweep", "--resume", Out("cut"), "--workers", "2", "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const std::vector<std::string> after = Lines(Out("cut") + "/results.jsonl");
  EXPECT_EQ(after.size(), 12u);
  EXPECT_EQ(ByJob(after), ByJob(Lines(Out("whole") + "/results.jsonl")));
  EXPECT_EQ(dir_.Read("cut/sweep.csv"), dir_.Read("whole/sweep.csv"));
}

TEST_F(BatchResumeTest, AScenarioChangedSinceTheInterruptionIsRefusedNamingIt) {
  const std::string scenario = dir_.Write("s.json", kScenario);
  const std::vector<std::string> before =
      Interrupt({"run", scenario, "--jobs", "8", "--workers", "1", "--quiet", "--out", Out("cut")}, Out("cut"), 1);
  ASSERT_LT(before.size(), 8u);
  nlohmann::json changed = nlohmann::json::parse(kScenario);
  changed["duration"] = 5.0;
  dir_.Write("s.json", changed.dump());
  const ProcessResult refused = RunProcess({kBatch, "run", "--resume", Out("cut")});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.err, HasSubstr(scenario + ": the scenario has changed since the batch in " + Out("cut")));
}

}  // namespace
}  // namespace orcs
