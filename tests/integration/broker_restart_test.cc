// Issue 7, "Done when": a broker killed with SIGKILL and restarted twice during a 200-job batch — every result
// arrives exactly once. The real programs on 127.0.0.1: orcs-broker with --journal, two orcs-worker processes
// that are never restarted, and a BatchClient. Each restart starts a new orcs-broker on the same ports and the
// same journal; the workers and the client find it by themselves.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "clients/runtime/batch_client.h"
#include "model/scene/scenario.h"
#include "tests/support/background_process.h"
#include "tests/support/broker_process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::PortOf;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
constexpr int kJobs = 200;

// One A-Series swinging its hips for 0.6 simulated seconds: a job of about 60 ms.
std::vector<v1::Job> Batch() {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "duration": 0.6,
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]}})");
  scene::ParseScenario(scenario, "restart");  // the client checks before submitting
  std::vector<v1::Job> jobs;
  for (int i = 0; i < kJobs; ++i) {
    v1::Job job;
    job.set_job_id("job-" + std::to_string(i));
    job.set_scenario_json(scenario.dump());
    job.set_genome_json(nlohmann::json({10.0 + 0.1 * i, 1.0, 0.0, 0.0, 10.0 + 0.1 * i, 1.0, 3.0, 0.0}).dump());
    job.set_seed(static_cast<std::uint64_t>(i));
    job.set_time_limit_seconds(60);
    jobs.push_back(std::move(job));
  }
  return jobs;
}

class BrokerRestartIntegrationTest : public ::testing::Test {
 protected:
  void StartBroker(const std::string& client_port, const std::string& worker_port) {
    test_support::BrokerProcess started = test_support::StartBrokerProcess(
        {"--client-port", client_port, "--worker-port", worker_port, "--heartbeat", "0.1", "--journal",
         dir_.PathOf("journal.db")});
    ASSERT_EQ(started.error, "");
    broker_ = std::move(started.process);
    clients_ = started.clients;
    workers_ = started.workers;
  }
  // SIGKILL, then a new broker on the same ports and journal; returns the old one's log.
  std::string KillAndRestartBroker() {
    broker_->Signal(SIGKILL);
    EXPECT_TRUE(broker_->Wait(milliseconds(10000)).has_value()) << "the broker survived SIGKILL";
    const std::string log = broker_->err();
    StartBroker(PortOf(clients_), PortOf(workers_));
    return log;
  }

  test_support::TempDir dir_;
  std::unique_ptr<BackgroundProcess> broker_;
  std::string clients_, workers_;
};

TEST_F(BrokerRestartIntegrationTest, BrokerKilledTwiceDuringABatchEveryResultArrivesOnce) {
  ASSERT_NO_FATAL_FAILURE(StartBroker("0", "0"));
  std::vector<std::unique_ptr<BackgroundProcess>> workers;
  for (const char* id : {"w0", "w1"}) {
    workers.push_back(std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", id}));
  }
  runtime::BatchClientOptions options;
  options.endpoint = clients_;
  options.heartbeat_interval = milliseconds(100);
  options.reconnect_timeout = milliseconds(60000);
  runtime::BatchClient client(options);
  client.Submit(Batch());

  std::map<std::string, v1::Result> results;
  std::vector<std::string> restart_logs;
  const std::vector<std::size_t> kill_after = {50, 120};
  std::size_t kills = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(240);
  while (results.size() < kJobs && std::chrono::steady_clock::now() < deadline) {
    if (kills < kill_after.size() && results.size() >= kill_after[kills]) {
      ASSERT_NO_FATAL_FAILURE(KillAndRestartBroker());
      ++kills;
    }
    std::optional<v1::Result> result = client.Next(milliseconds(100));
    if (!result) continue;
    EXPECT_FALSE(results.contains(result->job_id())) << "twice: " << result->job_id();
    results[result->job_id()] = *result;
  }
  ASSERT_EQ(kills, 2u);
  ASSERT_EQ(results.size(), static_cast<std::size_t>(kJobs)) << broker_->err();
  for (const auto& [id, result] : results) EXPECT_EQ(result.status(), v1::Result::OK) << id << ": " << result.message();
  for (const auto& worker : workers) EXPECT_FALSE(worker->Wait(milliseconds(0)).has_value()) << worker->err();

  // The last broker resumed from the journal: it kept the results of the jobs finished before it started.
  std::smatch restored;
  const std::string log = broker_->err();
  ASSERT_TRUE(std::regex_search(log, restored, std::regex("restored 1 batches, (\\d+) jobs queued again \\((\\d+) "
                                                          "of them were in flight\\), (\\d+) results kept")))
      << log;
  // A turn's results reach the client before its journal transaction commits, so a SIGKILL can leave the client
  // with results the journal lacks: those jobs run again and the client drops the repeats. Kept plus dropped
  // covers every result the client had at the kill.
  EXPECT_GE(std::stoi(restored[3]) + static_cast<int>(client.stats().duplicates_dropped),
            static_cast<int>(kill_after[1]))
      << log;
  EXPECT_LE(std::stoi(restored[1]) + std::stoi(restored[3]), kJobs);
  std::cout << "200 jobs, broker killed twice: " << results.size() << " results, each once; the last restart "
            << restored[0] << "; the client resubmitted " << client.stats().submit_messages - 1
            << " times and dropped " << client.stats().duplicates_dropped << " duplicate results\n";
}

}  // namespace
}  // namespace orcs
