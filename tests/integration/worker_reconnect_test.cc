// Issue 4, item 6: orcs-worker reconnects after a broker restart. The real programs on 127.0.0.1: an orcs-broker
// is killed with SIGKILL between two batches and a new one started on the same ports; the same orcs-worker
// process, never restarted, serves the second batch.
//
// Two ways the worker comes back, one test each: the new broker is up before the worker has noticed anything
// (its old socket reconnects by itself, the broker answers the unknown worker's heartbeat with DISCONNECT, the
// worker sends READY again), or only after the worker has given the silent broker up (a new socket that
// ZeroMQ keeps connecting until the broker listens).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "model/scene/scenario.h"
#include "tests/support/background_process.h"
#include "tests/support/batch_collector.h"
#include "tests/support/broker_process.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::PortOf;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
constexpr int kJobsPerBatch = 4;
constexpr char kWorkerId[] = "w0";

// One A-Series swinging its hips for a fifth of a simulated second: a job of a few milliseconds.
std::string ScenarioJson() {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "duration": 0.2,
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]}})");
  scene::ParseScenario(scenario, "reconnect");  // the client checks before submitting
  return scenario.dump();
}

std::vector<v1::Job> Batch(const std::string& name) {
  const std::string scenario = ScenarioJson();
  std::vector<v1::Job> jobs;
  for (int i = 0; i < kJobsPerBatch; ++i) {
    v1::Job job;
    job.set_job_id(name + "-" + std::to_string(i));
    job.set_scenario_json(scenario);
    job.set_genome_json(nlohmann::json({10.0 + i, 1.0, 0.0, 0.0, 10.0 + i, 1.0, 3.0, 0.0}).dump());
    job.set_seed(static_cast<std::uint64_t>(i));
    job.set_time_limit_seconds(60);
    jobs.push_back(std::move(job));
  }
  return jobs;
}

class WorkerReconnectTest : public ::testing::Test {
 protected:
  // Starts a broker on the given ports ("0" = any free one) with 0.1 s heartbeats and reads its endpoints.
  void StartBroker(const std::string& client_port, const std::string& worker_port) {
    test_support::BrokerProcess started = test_support::StartBrokerProcess(
        {"--client-port", client_port, "--worker-port", worker_port, "--heartbeat", "0.1"});
    ASSERT_EQ(started.error, "");
    broker_ = std::move(started.process);
    clients_ = started.clients;
    workers_ = started.workers;
  }
  // Kills the broker with SIGKILL and reaps it.
  void KillBroker() {
    broker_->Signal(SIGKILL);
    ASSERT_TRUE(broker_->Wait(milliseconds(10000)).has_value()) << "the broker survived SIGKILL";
  }
  void StartWorker() {
    worker_ = std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", kWorkerId});
  }
  bool WorkerRunning() { return !worker_->Wait(milliseconds(0)).has_value(); }
  // Waits (bounded) until the worker has written `text` to stderr.
  bool AwaitWorkerSays(const std::string& text, milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (worker_->err().find(text) == std::string::npos) {
      if (std::chrono::steady_clock::now() > deadline || worker_->Wait(milliseconds(50)).has_value()) return false;
    }
    return true;
  }
  // Runs `jobs` through a client of the current broker; every result ok and from the one worker.
  void RunBatchAllOk(std::vector<v1::Job> jobs) {
    const std::size_t count = jobs.size();
    const test_support::CollectedBatch batch =
        test_support::CollectBatch(clients_, std::move(jobs), std::chrono::seconds(60));
    EXPECT_THAT(batch.duplicate_ids, ::testing::IsEmpty());
    ASSERT_EQ(batch.results.size(), count) << "worker stderr:\n" << worker_->err();
    for (const auto& [id, result] : batch.results) {
      EXPECT_EQ(result.status(), v1::Result::OK) << id << ": " << result.message();
      EXPECT_EQ(result.worker_id(), kWorkerId) << id;
    }
  }

  std::unique_ptr<BackgroundProcess> broker_;
  std::unique_ptr<BackgroundProcess> worker_;
  std::string clients_, workers_;
};

TEST_F(WorkerReconnectTest, TheSameWorkerServesABrokerRestartedAtOnceOnTheSamePorts) {
  ASSERT_NO_FATAL_FAILURE(StartBroker("0", "0"));
  ASSERT_NO_FATAL_FAILURE(StartWorker());
  ASSERT_NO_FATAL_FAILURE(RunBatchAllOk(Batch("before")));
  const std::string client_port = PortOf(clients_), worker_port = PortOf(workers_);

  ASSERT_NO_FATAL_FAILURE(KillBroker());
  // Usually up before the worker's 0.5 s of patience are over: the new broker then sends the unknown worker
  // away ("said goodbye"); on a slow machine the worker may give up first. Either way it starts over.
  ASSERT_NO_FATAL_FAILURE(StartBroker(client_port, worker_port));
  ASSERT_EQ(PortOf(workers_), worker_port);
  ASSERT_TRUE(WorkerRunning()) << worker_->err();

  ASSERT_NO_FATAL_FAILURE(RunBatchAllOk(Batch("after")));
  EXPECT_TRUE(WorkerRunning()) << "the worker served the new broker without being restarted";
  EXPECT_THAT(worker_->err(), HasSubstr("connecting again"));
  EXPECT_THAT(worker_->err(), HasSubstr("answers again"));
}

TEST_F(WorkerReconnectTest, TheSameWorkerServesABrokerRestartedAfterItGaveTheOldOneUp) {
  ASSERT_NO_FATAL_FAILURE(StartBroker("0", "0"));
  ASSERT_NO_FATAL_FAILURE(StartWorker());
  ASSERT_NO_FATAL_FAILURE(RunBatchAllOk(Batch("before")));
  const std::string client_port = PortOf(clients_), worker_port = PortOf(workers_);

  ASSERT_NO_FATAL_FAILURE(KillBroker());
  // The worker notices the silence (5 heartbeats of 0.1 s) and starts over on a new socket, with no broker yet.
  ASSERT_TRUE(AwaitWorkerSays("connecting again", milliseconds(10000))) << worker_->err();
  ASSERT_NO_FATAL_FAILURE(StartBroker(client_port, worker_port));
  ASSERT_TRUE(WorkerRunning()) << worker_->err();

  ASSERT_NO_FATAL_FAILURE(RunBatchAllOk(Batch("after")));
  EXPECT_TRUE(WorkerRunning()) << "the worker served the new broker without being restarted";
  EXPECT_THAT(worker_->err(), HasSubstr("no answer from the broker"));
  EXPECT_THAT(worker_->err(), HasSubstr("answers again"));
}

}  // namespace
}  // namespace orcs
