// A batch session streams its jobs (docs/batch.md, "Large batches"): jobs made from a JobSource go out in a
// bounded window through a real BatchClient to a real Broker on 127.0.0.1 with echo workers, results are written as
// they come, and neither the client nor the broker ever holds more than the window, however large the batch.
#include "clients/runtime/batch_session.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/broker/test_peers.h"
#include "tests/support/temp_dir.h"

namespace orcs::runtime {
namespace {

using test_support::BrokerThread;
using test_support::EchoWorker;
using test_support::TempDir;
using test_support::TestBrokerOptions;
using test_support::TestClientOptions;
using test_support::TestWorkerOptions;
using test_support::WaitFor;

constexpr const char* kScenario = R"({
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]},
  "genome": [10, 1, 0, 0, 10, 1, 3, 0]
})";

struct Outcome {
  BatchSummary summary;
  runtime::BatchClientStats client;
  broker::BrokerStats broker;
  std::map<std::string, nlohmann::json> lines;  // results.jsonl by id
  std::size_t line_count = 0;
};

class BatchSessionTest : public ::testing::Test {
 protected:
  BatchSessionTest() : input_(LoadScenario(dir_.Write("scenario.json", kScenario))), genomes_{DefaultGenome(input_)} {}

  // Runs `source` through a fresh broker with two echo workers (credit 2 each) under `options`.
  Outcome Run(const JobSource& source, SessionOptions options, const std::string& out) {
    BrokerThread broker(TestBrokerOptions());
    EchoWorker first(TestWorkerOptions(broker.worker_endpoint(), "echo-1", 2));
    EchoWorker second(TestWorkerOptions(broker.worker_endpoint(), "echo-2", 2));
    Outcome outcome;
    {
      runtime::BatchClient client(TestClientOptions(broker.client_endpoint()));
      ResultsWriter writer((dir_.path() / out).string());
      std::ostringstream discard;
      ProgressDisplay progress(discard, source.size(), false, ProgressDisplay::Clock::now());
      outcome.summary = RunSession(client, source, writer, progress, options);
      writer.Finish();
      outcome.client = client.stats();
      // Every result is out, the client still connected: the broker holds nothing of the batch any more. (Within
      // 300 ms: the broker forgets an idle client, and with it its batch, only after 500 ms.)
      EXPECT_TRUE(WaitFor([&] { return broker.stats().jobs_held == 0; }, std::chrono::milliseconds(300)))
          << broker.stats().jobs_held;
      outcome.broker = broker.stats();
    }
    std::ifstream in(dir_.path() / out / "results.jsonl");
    for (std::string line; std::getline(in, line); ++outcome.line_count) {
      nlohmann::json json = nlohmann::json::parse(line);
      outcome.lines[json["id"].get<std::string>()] = json;
    }
    return outcome;
  }

  TempDir dir_;
  ScenarioInput input_;
  std::vector<Genome> genomes_;
};

TEST_F(BatchSessionTest, StreamsABatchFarLargerThanItsWindowAndNeverHoldsMore) {
  const RunJobSource source(input_, genomes_, {.seed = 1, .repeats = 3000});
  SessionOptions options;
  options.window_jobs = 40;
  const Outcome outcome = Run(source, options, "out");
  EXPECT_EQ(outcome.summary.jobs, 3000u);
  EXPECT_EQ(outcome.summary.ok, 3000u);
  EXPECT_FALSE(outcome.summary.interrupted);
  // Complete and unique: one line per job, each id once, each with its own job's seed and result.
  EXPECT_EQ(outcome.line_count, 3000u);
  ASSERT_EQ(outcome.lines.size(), 3000u);
  for (std::size_t i = 0; i < 3000; ++i) {
    const PlannedJob planned = source.Job(i);
    const auto line = outcome.lines.find(planned.job.job_id());
    ASSERT_NE(line, outcome.lines.end()) << planned.job.job_id();
    EXPECT_EQ(line->second["seed"], planned.job.seed());
    EXPECT_EQ(line->second["fitness"], 2.0 * static_cast<double>(planned.job.seed()) + 0.25);
  }
  // The window held: never more than 40 jobs outstanding at the client nor held at the broker, and it was used
  // (topped up in SUBMITs of at least a quarter of it, not one job at a time, not everything at once).
  EXPECT_LE(outcome.client.max_outstanding, 40u);
  EXPECT_GE(outcome.client.max_outstanding, 30u);
  EXPECT_LE(outcome.broker.jobs_held_peak, 40u);
  EXPECT_GE(outcome.client.submit_messages, 3000u / 40u);
  EXPECT_LE(outcome.client.submit_messages, 3000u / 10u + 1u);
  EXPECT_EQ(outcome.broker.jobs_accepted, 3000u);
}

TEST_F(BatchSessionTest, AWindowedBatchWritesWhatTheWholeBatchAtOnceWrites) {
  const RunJobSource source(input_, genomes_, {.seed = 5, .repeats = 400});
  SessionOptions whole;
  whole.window_jobs = 1000000;
  SessionOptions windowed;
  windowed.window_jobs = 7;
  const Outcome all_at_once = Run(source, whole, "whole");
  const Outcome streamed = Run(source, windowed, "windowed");
  EXPECT_EQ(all_at_once.client.max_outstanding, 400u);  // the old way: every job submitted at the start
  EXPECT_LE(streamed.client.max_outstanding, 7u);
  ASSERT_EQ(all_at_once.line_count, 400u);
  ASSERT_EQ(streamed.line_count, 400u);
  ASSERT_EQ(streamed.lines.size(), 400u);
  for (const auto& [id, line] : all_at_once.lines) {
    ASSERT_EQ(streamed.lines.count(id), 1u) << id;
    nlohmann::json a = line;
    nlohmann::json b = streamed.lines.at(id);
    for (nlohmann::json* json : {&a, &b}) {  // who ran it and when differ from run to run
      json->erase("worker");
      json->erase("timings");
    }
    EXPECT_EQ(a, b) << id;
  }
}

TEST_F(BatchSessionTest, TheByteBudgetBoundsTheWindowToo) {
  const RunJobSource source(input_, genomes_, {.seed = 1, .repeats = 200});
  SessionOptions options;
  // Room for five jobs (each carries its scenario): the window is at most that, plus the one job that crosses it.
  options.window_bytes = 5 * source.Job(0).job.ByteSizeLong();
  const Outcome outcome = Run(source, options, "out");
  EXPECT_EQ(outcome.summary.ok, 200u);
  EXPECT_EQ(outcome.lines.size(), 200u);
  EXPECT_LE(outcome.client.max_outstanding, 6u);
  EXPECT_LE(outcome.broker.jobs_held_peak, 6u);
}

}  // namespace
}  // namespace orcs::runtime
