// Issue 18 item 5, large batches stream: orcs-batch's session (RunSession with a RunJobSource, as `orcs-batch
// run`/`submit` use it) against the real orcs-broker and two real orcs-worker processes on 127.0.0.1, simulating
// for real. A batch many times the window comes back complete, each job once, with the bits the same batch gives
// when submitted all at once, and the client never had more than the window outstanding.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "clients/runtime/batch_session.h"
#include "tests/support/background_process.h"
#include "tests/support/broker_process.h"
#include "tests/support/temp_dir.h"

namespace orcs::batch {
using runtime::BatchSummary;
using runtime::Genome;
using runtime::JobSource;
using runtime::LoadScenario;
using runtime::ProgressDisplay;
using runtime::ReadGenomes;
using runtime::ResultsWriter;
using runtime::RunJobSource;
using runtime::RunSession;
using runtime::ScenarioInput;
using runtime::SessionOptions;
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::TempDir;

const std::string kBin = ORCS_BINARY_DIR "/bin/";

// Hip oscillators for 0.05 simulated seconds under two randomised parameter sets: real physics, quick.
constexpr const char* kScenario = R"({
  "name": "hips",
  "duration": 0.05,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]},
  "randomisation": {"sets": 2, "default_motor_model": true}
})";

constexpr const char* kGenomes = "[20, 2, 0, 0, 20, 2, 3, 0]\n[30, 1, 0, 5, 30, 1, 0, -5]\n";

class BatchStreamTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test_support::BrokerProcess started =
        test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
    ASSERT_EQ(started.error, "");
    broker_ = std::move(started.process);
    clients_ = started.clients;
    for (int i = 0; i < 2; ++i) {
      workers_.push_back(std::make_unique<BackgroundProcess>(std::vector<std::string>{
          kBin + "orcs-worker", "--connect", started.workers, "--heartbeat", "0.1", "--id", "w" + std::to_string(i)}));
    }
    input_ = LoadScenario(dir_.Write("hips.json", kScenario));
    genomes_ = ReadGenomes(dir_.Write("genomes.jsonl", kGenomes));
  }

  // Runs the batch through the broker with `window_jobs`; returns results.jsonl's lines by id (failing on a
  // repeated id) and the client's counters.
  std::map<std::string, nlohmann::json> Run(const JobSource& source, std::size_t window_jobs, const std::string& out,
                                            runtime::BatchClientStats& stats) {
    runtime::BatchClientOptions options;
    options.endpoint = clients_;
    options.heartbeat_interval = milliseconds(100);
    options.log = [](std::string_view) {};
    runtime::BatchClient client(options);
    ResultsWriter writer((dir_.path() / out).string());
    std::ostringstream discard;
    ProgressDisplay progress(discard, source.size(), false, ProgressDisplay::Clock::now());
    SessionOptions session;
    session.window_jobs = window_jobs;
    const BatchSummary summary = RunSession(client, source, writer, progress, session);
    writer.Finish();
    EXPECT_EQ(summary.ok + summary.failed, source.size());
    stats = client.stats();
    std::map<std::string, nlohmann::json> lines;
    std::ifstream in(dir_.path() / out / "results.jsonl");
    for (std::string line; std::getline(in, line);) {
      nlohmann::json json = nlohmann::json::parse(line);
      const std::string id = json["id"];
      EXPECT_FALSE(lines.contains(id)) << "repeated " << id;
      lines[id] = std::move(json);
    }
    return lines;
  }

  TempDir dir_;
  std::unique_ptr<BackgroundProcess> broker_;
  std::string clients_;
  std::vector<std::unique_ptr<BackgroundProcess>> workers_;
  ScenarioInput input_;
  std::vector<Genome> genomes_;
};

TEST_F(BatchStreamTest, ABatchTwentyWindowsLongComesBackCompleteOnceEachWithTheBitsOfTheWholeBatch) {
  const RunJobSource source(input_, genomes_, {.seed = 1, .repeats = 80});  // 160 jobs
  runtime::BatchClientStats streamed_stats;
  runtime::BatchClientStats whole_stats;
  const std::map<std::string, nlohmann::json> streamed = Run(source, 8, "streamed", streamed_stats);
  const std::map<std::string, nlohmann::json> whole = Run(source, source.size(), "whole", whole_stats);
  EXPECT_LE(streamed_stats.max_outstanding, 8u);
  EXPECT_EQ(whole_stats.max_outstanding, 160u);
  ASSERT_EQ(streamed.size(), 160u);
  ASSERT_EQ(whole.size(), 160u);
  for (std::size_t i = 0; i < source.size(); ++i) {
    const std::string id = source.Job(i).job.job_id();
    ASSERT_TRUE(streamed.contains(id)) << id;
    ASSERT_TRUE(whole.contains(id)) << id;
    nlohmann::json a = streamed.at(id);
    nlohmann::json b = whole.at(id);
    EXPECT_EQ(a["status"], "ok") << id << ": " << a["message"];
    for (nlohmann::json* json : {&a, &b}) {  // which worker ran it, and how long it waited, differ
      json->erase("worker");
      json->erase("timings");
    }
    EXPECT_EQ(a, b) << id;  // the same fitness, terms and drawn values, bit for bit
  }
}

}  // namespace
}  // namespace orcs::batch
