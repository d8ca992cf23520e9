// A batch through the real programs on 127.0.0.1: orcs-broker, orcs-worker processes, and a BatchClient.
// Issue 4's "Done when": 40 jobs on 2 workers all ok; the same batch on 1 worker gives the same bits; a worker
// killed with SIGKILL mid-batch loses no job and duplicates none; a bad genome fails alone with a message.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <map>
#include <regex>

#include "model/scene/scenario.h"
#include "tests/support/background_process.h"
#include "tests/support/batch_collector.h"
#include "tests/support/broker_process.h"

namespace orcs {
namespace {

using test_support::BackgroundProcess;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
constexpr int kJobs = 40;

// One A-Series swinging its hips, half a simulated second, under two randomised parameter sets.
std::string ScenarioJson() {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "duration": 0.5,
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]},
    "randomisation": {"sets": 2, "default_motor_model": true}})");
  scene::ParseScenario(scenario, "batch");  // the client checks before submitting
  return scenario.dump();
}

v1::Job Job(int i, const std::string& scenario) {
  v1::Job job;
  job.set_job_id("job-" + std::to_string(i));
  job.set_scenario_json(scenario);
  job.set_genome_json(nlohmann::json({10.0 + i, 1.0, 0.0, 0.0, 10.0 + i, 1.0, 3.0, 0.0}).dump());
  job.set_seed(static_cast<std::uint64_t>(1000 + i));
  job.set_time_limit_seconds(60);
  return job;
}

class BatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test_support::BrokerProcess started =
        test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
    ASSERT_EQ(started.error, "");
    broker_ = std::move(started.process);
    clients_ = started.clients;
    workers_ = started.workers;
  }
  void StartWorkers(int count) {
    for (int i = 0; i < count; ++i) {
      workers_processes_.push_back(std::make_unique<BackgroundProcess>(std::vector<std::string>{
          kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", "w" + std::to_string(i)}));
    }
  }
  // Submits `jobs` and collects results by job id, failing on a duplicate.
  std::map<std::string, v1::Result> RunBatch(std::vector<v1::Job> jobs, const std::function<void(int)>& on_result = {}) {
    const std::size_t count = jobs.size();
    test_support::CollectedBatch batch =
        test_support::CollectBatch(clients_, std::move(jobs), std::chrono::seconds(120), on_result);
    EXPECT_THAT(batch.duplicate_ids, ::testing::IsEmpty());
    EXPECT_EQ(batch.results.size(), count);
    return std::move(batch.results);
  }
  std::vector<v1::Job> Jobs() {
    const std::string scenario = ScenarioJson();
    std::vector<v1::Job> jobs;
    for (int i = 0; i < kJobs; ++i) jobs.push_back(Job(i, scenario));
    return jobs;
  }

  std::unique_ptr<BackgroundProcess> broker_;
  std::vector<std::unique_ptr<BackgroundProcess>> workers_processes_;
  std::string clients_, workers_;
};

TEST_F(BatchTest, FortyJobsOnTwoWorkersAllOkAndTheSameBitsOnOneWorker) {
  StartWorkers(2);
  const std::map<std::string, v1::Result> two = RunBatch(Jobs());
  std::set<std::string> worker_ids;
  for (const auto& [id, result] : two) {
    EXPECT_EQ(result.status(), v1::Result::OK) << id << ": " << result.message();
    EXPECT_EQ(result.parameter_sets_size(), 2);
    worker_ids.insert(result.worker_id());
  }
  EXPECT_EQ(worker_ids.size(), 2u) << "both workers got work";

  workers_processes_.clear();  // kills both
  StartWorkers(1);
  const std::map<std::string, v1::Result> one = RunBatch(Jobs());
  for (const auto& [id, result] : one) {
    ASSERT_TRUE(two.contains(id));
    const v1::Result& other = two.at(id);
    EXPECT_EQ(result.fitness(), other.fitness()) << id;  // bit for bit
    for (int k = 0; k < result.parameter_sets_size(); ++k) {
      for (int t = 0; t < result.parameter_sets(k).terms_size(); ++t) {
        EXPECT_EQ(result.parameter_sets(k).terms(t).value(), other.parameter_sets(k).terms(t).value()) << id;
      }
      for (int d = 0; d < result.parameter_sets(k).drawn_size(); ++d) {
        EXPECT_EQ(result.parameter_sets(k).drawn(d).value(), other.parameter_sets(k).drawn(d).value()) << id;
      }
    }
  }
}

TEST_F(BatchTest, AWorkerKilledMidBatchLosesNoJobAndDuplicatesNone) {
  StartWorkers(2);
  const std::map<std::string, v1::Result> results = RunBatch(Jobs(), [this](int received) {
    if (received == 5) workers_processes_[0]->Signal(SIGKILL);
  });
  for (const auto& [id, result] : results) EXPECT_EQ(result.status(), v1::Result::OK) << id << ": " << result.message();
}

TEST_F(BatchTest, ABadGenomeFailsAloneWithAMessage) {
  StartWorkers(1);
  std::vector<v1::Job> jobs = Jobs();
  jobs.resize(4);
  jobs[2].set_genome_json("[1, 2, 3]");
  const std::map<std::string, v1::Result> results = RunBatch(std::move(jobs));
  EXPECT_EQ(results.at("job-2").status(), v1::Result::INVALID_INPUT);
  EXPECT_THAT(results.at("job-2").message(), HasSubstr("field 'genome' expected 8 numbers, found an array of 3"));
  for (const char* id : {"job-0", "job-1", "job-3"}) EXPECT_EQ(results.at(id).status(), v1::Result::OK) << id;
}

}  // namespace
}  // namespace orcs
