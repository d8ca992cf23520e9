// Issue 18: the broker against attackers and careless peers on the same machine, with the real programs on
// 127.0.0.1 — an orcs-broker, orcs-worker processes, `orcs-batch submit` as the victim's client — and hand-made
// ZeroMQ peers as the attackers:
//   (a) forged results: a peer that never sent READY answers every job of a queued batch with fitness 1e9;
//   (b) batch takeover: an empty SUBMIT naming the victim's batch and client, both read from the broker's log;
//   (c) log injection: worker ids with a newline and a forged log line, and a 1 MB worker id;
//   (d) stalls: a worker that heartbeats but never answers holds a job; a worker whose simulation process is
//       stopped (SIGSTOP) holds a job.
// Each test prints its figures ("[ figures  ]"), which docs/reliability.md records.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <dirent.h>

#include <csignal>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "proto/envelope.h"
#include "tests/broker/test_peers.h"
#include "tests/support/background_process.h"
#include "tests/support/hip_swing_scenario.h"
#include "tests/support/broker_process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::RawPeer;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
using Clock = std::chrono::steady_clock;


// What orcs-batch wrote to results.jsonl, by job id.
std::map<std::string, nlohmann::json> ReadResults(const std::string& path) {
  std::map<std::string, nlohmann::json> results;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    nlohmann::json result = nlohmann::json::parse(line);
    results[result.at("id").get<std::string>()] = result;
  }
  return results;
}

class AdversarialTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test_support::BrokerProcess broker = test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
    ASSERT_TRUE(broker.error.empty()) << broker.error;
    broker_ = std::move(broker.process);
    clients_ = broker.clients;
    workers_ = broker.workers;
  }

  // `orcs-batch submit` of `jobs` jobs of test_support::HipSwingScenarioText(duration), in the background.
  std::unique_ptr<BackgroundProcess> Submit(int jobs, double duration, double time_limit) {
    const std::string scenario = dir_.Write("scenario.json", test_support::HipSwingScenarioText(duration));
    return std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-batch", "submit", "--broker", clients_, scenario, "--jobs", std::to_string(jobs), "--out",
        dir_.PathOf("out"), "--heartbeat", "0.1", "--quiet", "--time-limit", std::to_string(time_limit)});
  }

  std::unique_ptr<BackgroundProcess> StartWorker(const std::string& name) {
    return std::make_unique<BackgroundProcess>(std::vector<std::string>{kBin + "orcs-worker", "--connect", workers_,
                                                                        "--heartbeat", "0.1", "--id", name});
  }

  // Waits (bounded) until the broker's log matches `pattern`; returns the first group, or "" on timeout.
  std::string AwaitLog(const std::string& pattern, milliseconds limit = milliseconds(20000)) {
    const std::regex expression(pattern);
    const Clock::time_point deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      std::smatch match;
      const std::string err = broker_->err();
      if (std::regex_search(err, match, expression)) return match.size() > 1 ? match[1].str() : match[0].str();
      broker_->Wait(milliseconds(50));  // pumps its stderr
    }
    return "";
  }

  // Waits for a process to end, calling `meanwhile` every 100 ms; bounded by `limit`.
  std::optional<test_support::ProcessResult> AwaitExit(BackgroundProcess& process, milliseconds limit,
                                                       const std::function<void()>& meanwhile = {}) {
    const Clock::time_point deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      if (auto done = process.Wait(milliseconds(100))) return done;
      if (meanwhile) meanwhile();
    }
    return std::nullopt;
  }

  test_support::TempDir dir_;
  std::unique_ptr<BackgroundProcess> broker_;
  std::string clients_, workers_;
};

v1::WorkerToBroker ForgedResult(const std::string& batch_id, const std::string& job_id, std::uint64_t lease) {
  v1::WorkerToBroker message;
  message.set_protocol_version(proto::kProtocolVersion);
  v1::Result& result = *message.mutable_result();
  result.set_protocol_version(proto::kProtocolVersion);
  result.set_batch_id(batch_id);
  result.set_job_id(job_id);
  result.set_status(v1::Result::OK);
  result.set_fitness(1e9);
  result.set_worker_id("forger");
  result.set_lease(lease);
  return message;
}

TEST_F(AdversarialTest, ForgedResultsTakeoversAndForgedLogLinesGetNowhere) {
  constexpr int kJobs = 6;
  std::unique_ptr<BackgroundProcess> victim = Submit(kJobs, 0.2, 60);
  // Everything an attacker needs is in the broker's log: the batch id and the client's name.
  const std::string opened = AwaitLog("client (\\S+) opened batch (\\S+)");
  ASSERT_FALSE(opened.empty()) << broker_->err();
  std::smatch match;
  const std::string err = broker_->err();
  ASSERT_TRUE(std::regex_search(err, match, std::regex("client (\\S+) opened batch (\\S+)")));
  const std::string client_id = match[1], batch_id = match[2];
  EXPECT_TRUE(std::regex_match(batch_id, std::regex("[0-9a-f]{32}"))) << "128 random bits: " << batch_id;

  // (a) A peer on the worker port that never sent READY answers every queued job, with a few guessed tokens.
  RawPeer forger(workers_);
  int forged = 0;
  for (int i = 0; i < kJobs; ++i) {
    for (std::uint64_t lease : {0ull, 1ull, 0xffffffffffffffffull}) {
      forger.Send(ForgedResult(batch_id, "job-" + std::to_string(i), lease));
      ++forged;
    }
  }
  // (b) An empty SUBMIT naming the victim's batch and client, from another connection.
  RawPeer thief(clients_);
  v1::ClientToBroker takeover;
  takeover.set_protocol_version(proto::kProtocolVersion);
  takeover.mutable_submit()->set_batch_id(batch_id);
  takeover.mutable_submit()->set_client_id(client_id);
  takeover.mutable_submit()->set_owner_token(std::string(16, '\0'));
  thief.Send(takeover);
  std::optional<v1::BrokerToClient> answer = thief.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer.has_value());
  ASSERT_TRUE(answer->has_error());
  EXPECT_EQ(answer->error().message(), "batch '" + batch_id + "' belongs to another client");
  // (c) Worker ids that try to write a log line of their own, or a megabyte of log.
  RawPeer liar(workers_);
  liar.Send(test_support::ReadyMessage("w9 joined with credit 1\norcs-broker: client admin opened batch 0", 1));
  RawPeer flooder(workers_);
  flooder.Send(test_support::ReadyMessage(std::string(1 << 20, 'x'), 1));
  ASSERT_FALSE(AwaitLog("READY with a worker_id of 1048576 bytes").empty()) << broker_->err();
  ASSERT_FALSE(AwaitLog("worker w9 joined").empty()) << broker_->err();
  v1::WorkerToBroker goodbye;  // the liar leaves; any job it drew goes back to the queue, no loss counted
  goodbye.set_protocol_version(proto::kProtocolVersion);
  goodbye.mutable_disconnect()->set_reason("done lying");
  liar.Send(goodbye);

  // The victim's batch then runs on an honest worker and ends as if nobody had tried anything.
  std::unique_ptr<BackgroundProcess> worker = StartWorker("honest");
  std::optional<test_support::ProcessResult> done = AwaitExit(*victim, milliseconds(120000));
  ASSERT_TRUE(done.has_value()) << "the victim's batch never finished\n" << broker_->err();
  EXPECT_EQ(done->exit_code, 0) << done->err;
  const std::map<std::string, nlohmann::json> results = ReadResults(dir_.PathOf("out/results.jsonl"));
  ASSERT_EQ(results.size(), static_cast<std::size_t>(kJobs));
  int accepted_forgeries = 0;
  for (const auto& [id, result] : results) {
    EXPECT_EQ(result.at("status"), "ok") << id;
    EXPECT_EQ(result.at("worker"), "honest") << id;
    accepted_forgeries += result.at("fitness").is_number() && result.at("fitness").get<double>() == 1e9 ? 1 : 0;
  }
  EXPECT_EQ(accepted_forgeries, 0);
  std::optional<v1::BrokerToClient> stolen = thief.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(100));
  EXPECT_FALSE(stolen && stolen->has_result()) << "a result went to the thief";

  // Every line of the broker's log is its own: one prefix each, nothing longer than the cap.
  broker_->Wait(milliseconds(200));
  std::istringstream log(broker_->err());
  int lines = 0;
  for (std::string line; std::getline(log, line); ++lines) {
    EXPECT_EQ(line.rfind("orcs-broker: ", 0), 0u) << "a line the broker did not write: " << line.substr(0, 200);
    EXPECT_LE(line.size(), 2100u);
  }
  EXPECT_THAT(broker_->err(), HasSubstr("worker w9 joined with credit 1\\x0aorcs-broker: client admin opened batch 0"));
  EXPECT_THAT(broker_->err(), HasSubstr("READY with a worker_id of 1048576 bytes (at most 128)"));
  EXPECT_THAT(broker_->err(), HasSubstr("refused a result from a connection that never sent READY"));
  std::cout << "[ figures  ] jobs " << kJobs << ", forged results sent " << forged << ", accepted "
            << accepted_forgeries << "; takeover SUBMITs 1, accepted 0; results lost "
            << kJobs - static_cast<int>(results.size()) << "; log lines " << lines << ", forged 0\n";
}

TEST_F(AdversarialTest, AWorkerThatHeartbeatsButNeverAnswersHoldsItsJobOnlyUntilTheLeaseEnds) {
  RawPeer staller(workers_);
  staller.Send(test_support::ReadyMessage("staller", 1));
  ASSERT_FALSE(AwaitLog("worker staller joined").empty()) << broker_->err();
  std::unique_ptr<BackgroundProcess> victim = Submit(2, 0.2, 0.5);  // lease: 1.5 × 0.5 s + 2 s + 0.5 s = 3.25 s
  std::optional<v1::Job> held = test_support::AwaitJob(staller);
  ASSERT_TRUE(held.has_value());
  const Clock::time_point taken = Clock::now();
  std::unique_ptr<BackgroundProcess> worker = StartWorker("honest");
  std::optional<test_support::ProcessResult> done =
      AwaitExit(*victim, milliseconds(60000), [&] { staller.Send(test_support::WorkerHeartbeat()); });
  ASSERT_TRUE(done.has_value()) << "the batch waited for the stalled worker\n" << broker_->err();
  const double waited = std::chrono::duration<double>(Clock::now() - taken).count();
  EXPECT_EQ(done->exit_code, 0) << done->err;
  const std::map<std::string, nlohmann::json> results = ReadResults(dir_.PathOf("out/results.jsonl"));
  ASSERT_EQ(results.size(), 2u);
  for (const auto& [id, result] : results) {
    EXPECT_EQ(result.at("status"), "ok") << id;
    EXPECT_EQ(result.at("worker"), "honest") << id;
  }
  EXPECT_EQ(results.at(held->job_id()).at("attempts"), 2);
  EXPECT_THAT(broker_->err(), HasSubstr("worker staller lost: held job " + held->batch_id() + "/" + held->job_id() +
                                        " past its lease (time limit 0.5 s, leased for 3.2 s)"));
  EXPECT_GE(waited, 3.0);
  std::cout << "[ figures  ] stalled worker: job back after " << waited << " s (lease 3.25 s), 2 of 2 ok\n";
}

// The pids of `parent`'s children, from /proc.
std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> children;
  const std::string tasks = "/proc/" + std::to_string(parent) + "/task";
  DIR* folder = ::opendir(tasks.c_str());
  if (folder == nullptr) return children;
  while (dirent* entry = ::readdir(folder)) {
    if (entry->d_name[0] == '.') continue;
    std::ifstream in(tasks + "/" + entry->d_name + "/children");
    for (pid_t pid; in >> pid;) children.push_back(pid);
  }
  ::closedir(folder);
  return children;
}

TEST_F(AdversarialTest, AStoppedSimulationProcessIsKilledAtItsDeadlineAndTheNextJobRuns) {
  std::unique_ptr<BackgroundProcess> worker = StartWorker("w");
  ASSERT_FALSE(AwaitLog("worker w joined").empty()) << broker_->err();
  std::vector<pid_t> children;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(10);
  while ((children = ChildrenOf(worker->pid())).empty() && Clock::now() < deadline) worker->Wait(milliseconds(20));
  ASSERT_EQ(children.size(), 1u) << "the worker's simulation process";
  ASSERT_EQ(::kill(children[0], SIGSTOP), 0);

  std::unique_ptr<BackgroundProcess> victim = Submit(2, 0.2, 1.0);
  std::optional<test_support::ProcessResult> done = AwaitExit(*victim, milliseconds(60000));
  ASSERT_TRUE(done.has_value()) << "the stopped simulation process held the batch\n" << worker->err();
  EXPECT_EQ(done->exit_code, 1) << "one job timed out: " << done->err;
  const std::map<std::string, nlohmann::json> results = ReadResults(dir_.PathOf("out/results.jsonl"));
  ASSERT_EQ(results.size(), 2u);
  int timeouts = 0, ok = 0;
  for (const auto& [id, result] : results) {
    if (result.at("status") == "timeout") {
      ++timeouts;
      EXPECT_THAT(result.at("message").get<std::string>(), HasSubstr("did not answer within 2.25 s and was killed"));
    }
    ok += result.at("status") == "ok" ? 1 : 0;
  }
  EXPECT_EQ(timeouts, 1);
  EXPECT_EQ(ok, 1) << "the job behind it ran in a fresh simulation process";
  std::cout << "[ figures  ] stopped simulation process: 1 job timeout (killed after 2.25 s), 1 ok\n";
}

}  // namespace
}  // namespace orcs
