// The real orcs-broker program: its one-line endpoint announcement, bad input, a clean stop on SIGTERM, and
// workers and clients that live through a SIGKILL of the broker and its restart on the same ports.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <regex>
#include <set>

#include "tests/broker/test_peers.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"

namespace orcs::test_support {
namespace {

using std::chrono::milliseconds;
using ::testing::HasSubstr;

const std::string kBroker = ORCS_BINARY_DIR "/bin/orcs-broker";

struct Endpoints {
  std::string clients;
  std::string workers;
};

// Starts orcs-broker with `arguments` (plus a fast heartbeat) and reads the line it announces its endpoints on.
std::optional<Endpoints> StartBroker(std::unique_ptr<BackgroundProcess>& process, std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), {kBroker, "--heartbeat", "0.1"});
  process = std::make_unique<BackgroundProcess>(arguments);
  std::optional<std::string> line = process->ReadLine(milliseconds(10000));
  if (!line) return std::nullopt;
  std::smatch match;
  static const std::regex kLine(
      "orcs-broker clients=(tcp://127\\.0\\.0\\.1:[0-9]+) workers=(tcp://127\\.0\\.0\\.1:[0-9]+)");
  if (!std::regex_match(*line, match, kLine)) {
    ADD_FAILURE() << "unexpected first line: " << *line;
    return std::nullopt;
  }
  return Endpoints{match[1], match[2]};
}

int PortOf(const std::string& endpoint) { return std::stoi(endpoint.substr(endpoint.rfind(':') + 1)); }

std::vector<v1::Job> MakeJobs(int count) {
  std::vector<v1::Job> jobs;
  for (int i = 0; i < count; ++i) jobs.push_back(MakeJob("job-" + std::to_string(i), i));
  return jobs;
}

TEST(OrcsBroker, AnnouncesItsEndpointsServesAndStopsCleanlyOnSigterm) {
  std::unique_ptr<BackgroundProcess> process;
  const std::optional<Endpoints> endpoints = StartBroker(process, {"--client-port", "0", "--worker-port", "0"});
  ASSERT_TRUE(endpoints.has_value());
  {
    EchoWorker worker(TestWorkerOptions(endpoints->workers, "w", 2));
    runtime::BatchClient client(TestClientOptions(endpoints->clients));
    client.Submit(MakeJobs(20));
    std::set<std::string> ids;
    for (const v1::Result& result : Collect(client, 20)) {
      EXPECT_EQ(result.fitness(), EchoFitness(MakeJob(result.job_id(), std::stoull(result.job_id().substr(4)))));
      ids.insert(result.job_id());
    }
    EXPECT_EQ(ids.size(), 20u);
  }  // the worker and the client say goodbye
  EXPECT_TRUE(
      WaitFor([&] { return process->err().find("worker w left (worker shutting down)") != std::string::npos; }));
  process->Signal(SIGTERM);
  const std::optional<ProcessResult> result = process->Wait(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->exit_code, 0) << result->err;
  EXPECT_THAT(result->err, HasSubstr("worker w joined with credit 2"));
  EXPECT_THAT(result->err, HasSubstr("orcs-broker: stopped: told 0 workers and 0 clients"));
}

TEST(OrcsBroker, BadInputIsOneLineAndExitCodeTwo) {
  const auto expect_bad = [](const std::vector<std::string>& arguments, const std::string& expected) {
    std::vector<std::string> argv = {kBroker};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    const ProcessResult result = RunProcess(argv);
    EXPECT_EQ(result.exit_code, 2) << expected;
    EXPECT_THAT(result.err, HasSubstr(expected));
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_EQ(result.out, "");
  };
  expect_bad({"--bind", "192.0.2.1"},  // TEST-NET-1: never this machine's address
             "orcs-broker: cannot bind the client socket to tcp://192.0.2.1:5555: Cannot assign requested address");
  expect_bad({"--bind", "no-such-interface"}, "cannot bind the client socket to tcp://no-such-interface:5555");
  expect_bad({"--client-port", "70000"}, "--client-port");
  expect_bad({"--liveness", "1"}, "--liveness");
  expect_bad({"--client-port", "6000", "--worker-port", "6000"}, "--worker-port: must differ from --client-port");
  expect_bad({"--heartbeat", "soon"}, "--heartbeat");
  expect_bad({"--frobnicate"}, "frobnicate");

  BrokerThread occupant(TestBrokerOptions());
  const std::string busy = std::to_string(PortOf(occupant.worker_endpoint()));
  expect_bad({"--client-port", "0", "--worker-port", busy},
             "cannot bind the worker socket to tcp://127.0.0.1:" + busy + ": Address already in use");
}

TEST(OrcsBroker, HelpExitsZero) {
  const ProcessResult result = RunProcess({kBroker, "--help"});
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_THAT(result.out, HasSubstr("--worker-port"));
}

TEST(OrcsBroker, WorkersAndClientsLiveThroughABrokerKilledAndStartedAgain) {
  std::unique_ptr<BackgroundProcess> process;
  const std::optional<Endpoints> first = StartBroker(process, {"--client-port", "0", "--worker-port", "0"});
  ASSERT_TRUE(first.has_value());
  LogLines log;
  EchoWorker worker(TestWorkerOptions(first->workers, "w", 2, &log), milliseconds(10));
  runtime::BatchClient client(TestClientOptions(first->clients, &log));
  client.Submit(MakeJobs(40));
  std::vector<v1::Result> results = Collect(client, 5);
  ASSERT_EQ(results.size(), 5u);

  process->Signal(SIGKILL);  // no goodbye: the peers find out from the silence
  ASSERT_TRUE(process->Wait(milliseconds(10000)).has_value());
  const std::optional<Endpoints> second =
      StartBroker(process, {"--client-port", std::to_string(PortOf(first->clients)), "--worker-port",
                            std::to_string(PortOf(first->workers))});
  ASSERT_TRUE(second.has_value());
  for (v1::Result& result : Collect(client, 35)) results.push_back(std::move(result));
  std::set<std::string> ids;
  for (const v1::Result& result : results) ids.insert(result.job_id());
  EXPECT_EQ(results.size(), 40u);
  EXPECT_EQ(ids.size(), 40u);
  EXPECT_EQ(client.Next(milliseconds(300)), std::nullopt);
  EXPECT_GE(worker.connection().stats().connections, 2u);
  EXPECT_GE(client.stats().connections, 2u);
  process->Signal(SIGTERM);
  const std::optional<ProcessResult> end = process->Wait(milliseconds(10000));
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(end->exit_code, 0) << end->err;
}

}  // namespace
}  // namespace orcs::test_support
