// CURVE with the real programs on 127.0.0.1 (issue 7 item 5, docs/security.md): keys made by orcs-keys, an
// orcs-broker and an orcs-worker with --curve-keys, and orcs-batch submitting to them — with the allowed client
// key it gets every result; with an unknown key or none it cannot submit (exit 2, the reason on stderr) and the
// broker logs the refusal; a worker with an unknown key gets no job. And orcs-batch run --curve-keys end to end.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

using Clock = std::chrono::steady_clock;
const std::string kBin = ORCS_BINARY_DIR "/bin/";

// Hip oscillators for a fifth of a second: a job of a few milliseconds of simulation.
constexpr const char* kScenario = R"({
  "name": "hips",
  "duration": 0.2,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]},
  "genome": [20, 2, 0, 0, 20, 2, 3, 0]
})";

std::vector<nlohmann::json> ReadLines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// Waits until `process` has written `needle` to stderr, or `limit` has passed.
bool AwaitErr(BackgroundProcess& process, const std::string& needle, milliseconds limit = milliseconds(10000)) {
  const Clock::time_point deadline = Clock::now() + limit;
  while (process.err().find(needle) == std::string::npos) {
    if (Clock::now() >= deadline) return false;
    if (process.Wait(milliseconds(20))) return process.err().find(needle) != std::string::npos;  // it ended
  }
  return true;
}

class CurveProgramsTest : public ::testing::Test {
 protected:
  // keys/: the cluster's folder (broker, worker, client; worker.pub and client.pub allowed), made with orcs-keys
  // as docs/security.md says; stranger/: a worker and a client pair the broker does not know, and broker.pub.
  void SetUp() override {
    Run({kBin + "orcs-keys", "generate", Keys(), "broker", "worker", "client"});
    fs::create_directory(Keys() + "/allowed_workers");
    fs::create_directory(Keys() + "/allowed_clients");
    fs::copy_file(Keys() + "/worker.pub", Keys() + "/allowed_workers/node.pub");
    fs::copy_file(Keys() + "/client.pub", Keys() + "/allowed_clients/alice.pub");
    Run({kBin + "orcs-keys", "generate", Stranger(), "worker", "client"});
    fs::copy_file(Keys() + "/broker.pub", Stranger() + "/broker.pub");
    scenario_ = dir_.Write("hips.json", kScenario);
  }

  void Run(const std::vector<std::string>& argv) {
    const ProcessResult result = RunProcess(argv);
    ASSERT_EQ(result.exit_code, 0) << result.err;
  }
  std::string Keys() const { return dir_.PathOf("keys"); }
  std::string Stranger() const { return dir_.PathOf("stranger"); }

  void StartBroker() {
    broker_ = std::make_unique<BackgroundProcess>(
        std::vector<std::string>{kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0", "--heartbeat",
                                 "0.1", "--curve-keys", Keys()});
    const std::optional<std::string> line = broker_->ReadLine(milliseconds(10000));
    ASSERT_TRUE(line.has_value()) << broker_->err();
    std::smatch match;
    static const std::regex kLine("orcs-broker clients=(\\S+) workers=(\\S+)");
    ASSERT_TRUE(std::regex_match(*line, match, kLine)) << *line;
    clients_ = match[1];
    workers_ = match[2];
  }
  std::unique_ptr<BackgroundProcess> StartWorker(const std::string& id, const std::string& keys) {
    return std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-worker", "--connect", workers_, "--id", id, "--heartbeat", "0.1", "--curve-keys", keys});
  }
  ProcessResult Submit(const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {kBin + "orcs-batch", "submit", "--broker", clients_, scenario_, "--jobs", "3",
                                     "--heartbeat", "0.1", "--out", dir_.PathOf(out), "--quiet"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return RunProcess(argv);
  }

  TempDir dir_;
  std::string scenario_;
  std::unique_ptr<BackgroundProcess> broker_;
  std::string clients_;
  std::string workers_;
};

TEST_F(CurveProgramsTest, AllowedClientGetsEveryResultOthersCannotSubmit) {
  StartBroker();
  std::unique_ptr<BackgroundProcess> worker = StartWorker("allowed", Keys());
  ASSERT_TRUE(AwaitErr(*broker_, "worker allowed joined")) << broker_->err();

  const ProcessResult allowed = Submit("allowed", {"--curve-keys", Keys()});
  ASSERT_EQ(allowed.exit_code, 0) << allowed.err;
  const std::vector<nlohmann::json> lines = ReadLines(dir_.PathOf("allowed/results.jsonl"));
  ASSERT_EQ(lines.size(), 3u);
  std::set<std::string> ids;
  for (const nlohmann::json& line : lines) {
    EXPECT_EQ(line["status"], "ok") << line.dump();
    EXPECT_EQ(line["worker"], "allowed");
    ids.insert(line["id"].get<std::string>());
  }
  EXPECT_EQ(ids.size(), 3u);

  const ProcessResult stranger = Submit("stranger", {"--curve-keys", Stranger()});
  EXPECT_EQ(stranger.exit_code, 2);
  EXPECT_THAT(stranger.err, AllOf(HasSubstr("no broker answering at " + clients_), HasSubstr("the key was refused")));
  EXPECT_FALSE(fs::exists(dir_.PathOf("stranger/results.jsonl")));
  EXPECT_TRUE(AwaitErr(*broker_, "refused a client connection from 127.0.0.1")) << broker_->err();

  const ProcessResult plain = Submit("plain", {});
  EXPECT_EQ(plain.exit_code, 2);
  EXPECT_THAT(plain.err, HasSubstr("no broker answering at " + clients_));
  EXPECT_FALSE(fs::exists(dir_.PathOf("plain/results.jsonl")));

  // Only the allowed client's batch ever opened at the broker.
  const std::string log = broker_->err();
  std::size_t opened = 0;
  for (std::size_t at = log.find("opened batch"); at != std::string::npos; at = log.find("opened batch", at + 1)) {
    ++opened;
  }
  EXPECT_EQ(opened, 1u) << log;
}

TEST_F(CurveProgramsTest, WorkerWithUnknownKeyGetsNoJob) {
  StartBroker();
  std::unique_ptr<BackgroundProcess> stranger = StartWorker("stranger", Stranger());
  ASSERT_TRUE(AwaitErr(*stranger, "the key was refused")) << stranger->err();
  ASSERT_TRUE(AwaitErr(*broker_, "refused a worker connection from 127.0.0.1")) << broker_->err();
  std::unique_ptr<BackgroundProcess> allowed = StartWorker("allowed", Keys());
  ASSERT_TRUE(AwaitErr(*broker_, "worker allowed joined")) << broker_->err();

  const ProcessResult batch = Submit("batch", {"--curve-keys", Keys()});
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  const std::vector<nlohmann::json> lines = ReadLines(dir_.PathOf("batch/results.jsonl"));
  ASSERT_EQ(lines.size(), 3u);
  for (const nlohmann::json& line : lines) EXPECT_EQ(line["worker"], "allowed");
  EXPECT_EQ(broker_->err().find("worker stranger"), std::string::npos) << broker_->err();
}

TEST_F(CurveProgramsTest, RunWithEmbeddedBrokerAndLocalWorkers) {
  std::vector<std::string> argv = {kBin + "orcs-batch", "run",          scenario_,          "--jobs", "2",
                                   "--workers",         "1",            "--curve-keys",     Keys(),   "--out",
                                   dir_.PathOf("run"),  "--heartbeat", "0.1",              "--quiet"};
  const ProcessResult run = RunProcess(argv);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(ReadLines(dir_.PathOf("run/results.jsonl")).size(), 2u);
  const std::string log = dir_.Read(dir_.PathOf("run/workers.log"));
  EXPECT_THAT(log, HasSubstr("CURVE on (keys in " + Keys() + "): 1 worker keys and 1 client keys allowed"));
  EXPECT_THAT(log, HasSubstr("worker local-0 joined"));

  argv[8] = Stranger();  // no broker.key there: one line naming the file, exit 2
  const ProcessResult bad = RunProcess(argv);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err, "orcs-batch: " + Stranger() + "/broker.key: no such file\n");
}

}  // namespace
}  // namespace orcs
