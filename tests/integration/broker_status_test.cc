// Issue 21 item 1: `orcs-broker status` against the real orcs-broker, orcs-worker processes and `orcs-batch submit`
// on 127.0.0.1. During a batch it shows both workers busy on distinct jobs and the batch's counts adding up; after
// one worker is SIGKILLed it shows one worker and the lost one counted, and the batch still completes. A batch
// submitted while no worker is connected says so, keeps waiting, and completes once a worker joins.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/background_process.h"
#include "tests/support/hip_swing_scenario.h"
#include "tests/support/broker_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::RunProcess;
using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;

const std::string kBin = ORCS_BINARY_DIR "/bin/";


class BrokerStatusTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test_support::BrokerProcess broker =
        test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
    ASSERT_TRUE(broker.error.empty()) << broker.error;
    broker_ = std::move(broker.process);
    clients_ = broker.clients;
    workers_ = broker.workers;
  }

  std::unique_ptr<BackgroundProcess> StartWorker(const std::string& name) {
    return std::make_unique<BackgroundProcess>(std::vector<std::string>{kBin + "orcs-worker", "--connect", workers_,
                                                                        "--heartbeat", "0.1", "--id", name});
  }

  std::unique_ptr<BackgroundProcess> Submit(int jobs, double duration, const std::vector<std::string>& extra = {}) {
    const std::string scenario = dir_.Write("scenario.json", test_support::HipSwingScenarioText(duration, "status-test"));
    std::vector<std::string> argv = {kBin + "orcs-batch", "submit", "--broker", clients_, scenario, "--jobs",
                                     std::to_string(jobs), "--out", dir_.PathOf("out"), "--heartbeat", "0.1"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return std::make_unique<BackgroundProcess>(argv);
  }

  // `orcs-broker status --json`, parsed.
  Json Status() {
    const test_support::ProcessResult result =
        RunProcess({kBin + "orcs-broker", "status", "--broker", clients_, "--json"});
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return result.exit_code == 0 ? Json::parse(result.out) : Json::object();
  }

  // Asks for the status until `condition` holds (bounded); the last status either way.
  Json AwaitStatus(const std::function<bool(const Json&)>& condition, milliseconds limit = milliseconds(30000)) {
    const Clock::time_point deadline = Clock::now() + limit;
    Json status = Status();
    while (!condition(status) && Clock::now() < deadline) {
      broker_->Wait(milliseconds(50));  // pumps its stderr while we wait
      status = Status();
    }
    return status;
  }

  test_support::TempDir dir_;
  std::unique_ptr<BackgroundProcess> broker_;
  std::string clients_, workers_;
};

// Every job of the batch is in exactly one of its four counts.
std::uint64_t Accounted(const Json& batch) {
  return batch["queued"].get<std::uint64_t>() + batch["running"].get<std::uint64_t>() +
         batch["done"].get<std::uint64_t>() + batch["failed"].get<std::uint64_t>();
}

TEST_F(BrokerStatusTest, ShowsBusyWorkersAndTheBatchDuringARunAndOneWorkerLessAfterAKill) {
  auto w0 = StartWorker("w0");
  auto w1 = StartWorker("w1");
  Json status = AwaitStatus([](const Json& s) { return s.value("workers", 0) == 2; });
  ASSERT_EQ(status["workers"], 2) << status.dump();
  EXPECT_EQ(status["batch_list"].size(), 0u);

  constexpr int kJobs = 12;
  auto submit = Submit(kJobs, 10.0, {"--quiet"});
  status = AwaitStatus([](const Json& s) {
    return s.value("busy_workers", 0) == 2 && s["batch_list"].size() == 1 && s["batch_list"][0].value("done", 0) > 0;
  });
  ASSERT_EQ(status["busy_workers"], 2) << status.dump(1);
  ASSERT_EQ(status["batch_list"].size(), 1u) << status.dump(1);
  const Json batch = status["batch_list"][0];
  EXPECT_EQ(batch["expected"], kJobs);
  EXPECT_EQ(Accounted(batch), kJobs) << batch.dump();
  EXPECT_FALSE(batch["hidden"].get<bool>());
  EXPECT_GT(batch["jobs_per_second"].get<double>(), 0.0);
  std::set<std::string> current;
  std::uint64_t holding = 0;
  for (const Json& worker : status["worker_list"]) {
    EXPECT_TRUE(worker["busy"].get<bool>());
    EXPECT_EQ(worker["current_batch_id"], batch["batch_id"]);
    current.insert(worker["current_job_id"].get<std::string>());
    holding += worker["holding"].get<std::uint64_t>();
    EXPECT_FALSE(worker["host"].get<std::string>().empty());
  }
  EXPECT_EQ(current.size(), 2u) << "two workers, two different jobs: " << status.dump(1);
  EXPECT_EQ(status["running"], holding);
  EXPECT_EQ(batch["running"], holding);

  w0->Signal(SIGKILL);
  status = AwaitStatus([](const Json& s) { return s.value("workers", 0) == 1; });
  ASSERT_EQ(status["workers"], 1) << status.dump(1);
  EXPECT_EQ(status["worker_list"][0]["worker_id"], "w1");
  EXPECT_EQ(status["workers_lost"], 1);
  if (status["batch_list"].size() == 1) {
    EXPECT_EQ(Accounted(status["batch_list"][0]), kJobs);  // the killed worker's jobs are queued again
  }

  const std::optional<test_support::ProcessResult> done = submit->Wait(milliseconds(120000));
  ASSERT_TRUE(done.has_value()) << "the batch did not complete on the remaining worker";
  EXPECT_EQ(done->exit_code, 0) << done->err;
  status = AwaitStatus([](const Json& s) { return s["batch_list"].empty(); });
  EXPECT_EQ(status["done"], kJobs);  // the killed worker's jobs ran again elsewhere, each counted once
  EXPECT_EQ(status["failed"], 0);

  const test_support::ProcessResult text = RunProcess({kBin + "orcs-broker", "status", "--broker", clients_});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_THAT(text.out, HasSubstr("1 workers (0 busy)"));
  EXPECT_THAT(text.out, HasSubstr("WORKER"));
  EXPECT_THAT(text.out, HasSubstr("w1"));
}

TEST_F(BrokerStatusTest, ABatchWithoutWorkersSaysSoKeepsWaitingAndCompletesWhenOneJoins) {
  auto submit = Submit(2, 0.2);
  const Clock::time_point deadline = Clock::now() + milliseconds(30000);
  while (submit->err().find("no worker is connected") == std::string::npos && Clock::now() < deadline) {
    ASSERT_FALSE(submit->Wait(milliseconds(100)).has_value()) << "orcs-batch ended without a worker";
  }
  ASSERT_THAT(submit->err(), HasSubstr("no worker is connected to the broker"));
  EXPECT_THAT(submit->err(), HasSubstr("orcs-worker --connect " + workers_));
  EXPECT_EQ(Status()["queued"], 2);

  auto worker = StartWorker("late");
  const std::optional<test_support::ProcessResult> done = submit->Wait(milliseconds(60000));
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->exit_code, 0) << done->err;
  std::ifstream results(dir_.PathOf("out/results.jsonl"));
  int lines = 0;
  for (std::string line; std::getline(results, line);) lines += line.empty() ? 0 : 1;
  EXPECT_EQ(lines, 2);
}

// A newcomer's paper cut (issue 52): with no worker the status suggested `orcs-worker --broker …`, which answers
// "--connect is required". The command it suggests now is run as it is printed, and a worker joins.
TEST_F(BrokerStatusTest, WithNoWorkerItSuggestsACommandThatStartsOneAsPrinted) {
  const test_support::ProcessResult text = RunProcess({kBin + "orcs-broker", "status", "--broker", clients_});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  const std::size_t open = text.out.find("start one with `");
  ASSERT_NE(open, std::string::npos) << text.out;
  const std::size_t from = open + std::string("start one with `").size();
  const std::string command = text.out.substr(from, text.out.find('`', from) - from);
  std::vector<std::string> argv;
  std::istringstream words(command);
  for (std::string word; words >> word;) argv.push_back(word);
  ASSERT_EQ(argv.front(), "orcs-worker") << command;
  argv.front() = kBin + "orcs-worker";
  BackgroundProcess worker(argv);
  const Json status = AwaitStatus([](const Json& s) { return s.value("workers", 0) == 1; });
  EXPECT_EQ(status.value("workers", 0), 1) << "`" << command << "` did not start a worker: " << worker.err();
}

TEST_F(BrokerStatusTest, NoBrokerAtTheEndpointIsOneLineAndExit1WithinTheTimeout) {
  const std::string nobody = clients_;  // once its broker is gone
  broker_->Signal(SIGKILL);
  broker_->Wait(milliseconds(5000));
  const Clock::time_point start = Clock::now();
  const test_support::ProcessResult result =
      RunProcess({kBin + "orcs-broker", "status", "--broker", nobody, "--timeout", "0.5"});
  EXPECT_LT(Clock::now() - start, milliseconds(5000));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_THAT(result.err, HasSubstr("no broker answering at " + nobody + " after 0.5 s"));
  const test_support::ProcessResult bad = RunProcess({kBin + "orcs-broker", "status", "--broker", "nonsense"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("--broker"));
}

}  // namespace
}  // namespace orcs
