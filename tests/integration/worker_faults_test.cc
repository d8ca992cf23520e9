// Issue 7, crash isolation: faults injected into a batch run by the real programs on 127.0.0.1 — an orcs-broker,
// several orcs-worker processes (each running its jobs in a sandboxed simulation process) and a BatchClient.
//   (a) Workers SIGKILLed at three points of a 200-job batch, a replacement started each time: every result
//       arrives exactly once, all OK, with the fitness of a run without faults.
//   (b) One job segfaults the physics: it crashes three workers' simulation processes, is reported CRASHED as
//       poisonous, every other job finishes OK, and every worker process is still running.
// docs/reliability.md ("Fault tests") lists them with the figures of the last run, which each test prints.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <iostream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "model/scene/scenario.h"
#include "tests/support/background_process.h"
#include "tests/support/batch_collector.h"
#include "worker/job/job_translation.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kBin = ORCS_BINARY_DIR "/bin/";

// One A-Series swinging its hips for a fifth of a simulated second: a short job. `fault` when not null.
std::string ScenarioJson(const nlohmann::json& fault = nullptr) {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "duration": 0.2,
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]}})");
  if (!fault.is_null()) scenario["fault"] = fault;
  scene::ParseScenario(scenario, "faults");  // the client checks before submitting
  return scenario.dump();
}

std::vector<v1::Job> Jobs(int count) {
  const std::string scenario = ScenarioJson();
  std::vector<v1::Job> jobs;
  for (int i = 0; i < count; ++i) {
    v1::Job job;
    job.set_job_id("job-" + std::to_string(i));
    job.set_scenario_json(scenario);
    job.set_genome_json(nlohmann::json({10.0 + 0.1 * i, 1.0, 0.0, 0.0, 10.0 + 0.1 * i, 1.0, 3.0, 0.0}).dump());
    job.set_seed(static_cast<std::uint64_t>(5000 + i));
    job.set_time_limit_seconds(60);
    jobs.push_back(std::move(job));
  }
  return jobs;
}

class WorkerFaultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    broker_ = std::make_unique<BackgroundProcess>(std::vector<std::string>{kBin + "orcs-broker", "--client-port", "0",
                                                                           "--worker-port", "0", "--heartbeat", "0.1"});
    const std::optional<std::string> line = broker_->ReadLine(milliseconds(10000));
    ASSERT_TRUE(line.has_value()) << broker_->err();
    std::smatch match;
    static const std::regex kLine("orcs-broker clients=(\\S+) workers=(\\S+)");
    ASSERT_TRUE(std::regex_match(*line, match, kLine)) << *line;
    clients_ = match[1];
    workers_endpoint_ = match[2];
  }
  // Starts worker "w<n>" (n counts every worker this test started).
  void StartWorker() {
    const std::string name = "w" + std::to_string(workers_.size());
    workers_.push_back(std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-worker", "--connect", workers_endpoint_, "--heartbeat", "0.1", "--id", name}));
  }
  bool Running(BackgroundProcess& process) { return !process.Wait(milliseconds(0)).has_value(); }

  // Submits `jobs`, calls `on_result` with the number received after each, and collects the results by job id;
  // `duplicates` counts results for a job id already received.
  std::map<std::string, v1::Result> RunBatch(std::vector<v1::Job> jobs, int& duplicates,
                                             const std::function<void(int)>& on_result = {}) {
    test_support::CollectedBatch batch =
        test_support::CollectBatch(clients_, std::move(jobs), std::chrono::seconds(300), on_result);
    duplicates += static_cast<int>(batch.duplicate_ids.size());
    return std::move(batch.results);
  }

  std::unique_ptr<BackgroundProcess> broker_;
  std::vector<std::unique_ptr<BackgroundProcess>> workers_;
  std::string clients_, workers_endpoint_;
};

TEST_F(WorkerFaultsTest, WorkersKilledThreeTimesInA200JobBatchLoseNothingAndDuplicateNothing) {
  constexpr int kJobs = 200;
  const std::vector<int> kill_after = {40, 90, 140};  // results received; spread over the batch
  for (int i = 0; i < 3; ++i) StartWorker();
  int kills = 0;
  int duplicates = 0;
  const std::map<std::string, v1::Result> results = RunBatch(Jobs(kJobs), duplicates, [&](int received) {
    if (kills < 3 && received == kill_after[kills]) {
      workers_[kills]->Signal(SIGKILL);  // the oldest worker still running: it holds jobs, the queue is not empty
      ++kills;
      StartWorker();
    }
  });
  ASSERT_EQ(kills, 3);
  int retried = 0;
  for (const v1::Job& job : Jobs(kJobs)) {
    ASSERT_TRUE(results.contains(job.job_id())) << job.job_id() << " lost\nbroker:\n" << broker_->err();
    const v1::Result& result = results.at(job.job_id());
    EXPECT_EQ(result.status(), v1::Result::OK) << job.job_id() << ": " << result.message();
    const v1::Result reference = worker::RunJob(job);  // the run without faults: in this process, no broker
    EXPECT_EQ(result.fitness(), reference.fitness()) << job.job_id();  // bit for bit
    retried += static_cast<int>(result.attempts()) - 1;
  }
  EXPECT_EQ(duplicates, 0);
  EXPECT_GE(retried, 3) << "each kill hit at least the job its worker was running";
  for (int i = 3; i < 6; ++i) EXPECT_TRUE(Running(*workers_[i])) << "replacement w" << i;
  std::cout << "[ figures  ] jobs " << kJobs << ", workers SIGKILLed 3, results " << results.size() << ", lost "
            << kJobs - static_cast<int>(results.size()) << ", duplicates " << duplicates << ", jobs re-run " << retried
            << "\n";
}

TEST_F(WorkerFaultsTest, ASegfaultingJobIsPoisonousAndTheOthersAndTheWorkersCarryOn) {
  constexpr int kJobs = 24;
  constexpr int kPoison = 7;
  for (int i = 0; i < 3; ++i) StartWorker();
  std::vector<v1::Job> jobs = Jobs(kJobs);
  jobs[kPoison].set_scenario_json(ScenarioJson({{"kind", "segfault"}, {"at_step", 5}}));
  int duplicates = 0;
  const std::map<std::string, v1::Result> results = RunBatch(jobs, duplicates);
  ASSERT_EQ(results.size(), static_cast<std::size_t>(kJobs)) << "broker:\n" << broker_->err();
  const v1::Result& poison = results.at("job-" + std::to_string(kPoison));
  EXPECT_EQ(poison.status(), v1::Result::CRASHED);
  EXPECT_THAT(poison.message(), StartsWith("poisonous: crashed 3 workers (w"));
  EXPECT_THAT(poison.message(), HasSubstr("the last: the simulation process died of SIGSEGV (Segmentation fault)"));
  EXPECT_EQ(poison.attempts(), 3u);
  int ok = 0;
  for (const auto& [id, result] : results) {
    if (id == poison.job_id()) continue;
    EXPECT_EQ(result.status(), v1::Result::OK) << id << ": " << result.message();
    ok += result.status() == v1::Result::OK ? 1 : 0;
  }
  EXPECT_EQ(duplicates, 0);
  int crashes_logged = 0;
  for (const std::unique_ptr<BackgroundProcess>& worker : workers_) {
    EXPECT_TRUE(Running(*worker)) << "a worker survived the crashes of its simulation process";
    const std::string& err = worker->err();
    int crashes_here = 0;
    for (std::size_t at = err.find("died of SIGSEGV"); at != std::string::npos;
         at = err.find("died of SIGSEGV", at + 1)) {
      ++crashes_here;
    }
    // The broker hands a crashed job to a worker it has not crashed yet: one crash on each of the three.
    EXPECT_EQ(crashes_here, 1) << err;
    crashes_logged += crashes_here;
  }
  EXPECT_EQ(crashes_logged, 3) << "each crash in the log of the worker it happened to";
  EXPECT_THAT(broker_->err(), HasSubstr("poisonous: crashed 3 workers"));
  std::cout << "[ figures  ] jobs " << kJobs << ", segfaulting jobs 1, simulation crashes " << crashes_logged << ", ok "
            << ok << ", crashed " << (poison.status() == v1::Result::CRASHED ? 1 : 0) << ", lost "
            << kJobs - static_cast<int>(results.size()) << ", duplicates " << duplicates << ", workers still running "
            << workers_.size() << "\n[ figures  ] " << poison.job_id() << ": " << poison.message() << "\n";
}

}  // namespace
}  // namespace orcs
