// Plug-ins on workers (issue 50, docs/extending.md "Plug-ins") through the real programs on 127.0.0.1: orcs-broker,
// orcs-worker --plugins build/plugins (the example plug-in the project's CMake builds) and orcs-batch submit. A job
// naming the example's controller and fitness term runs on the worker that has them; a worker without them refuses
// the job with PLUGIN_MISSING, naming the plug-in; a bad plug-in folder stops a worker at its start.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <sstream>

#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
const std::string kPlugins = ORCS_BINARY_DIR "/plugins";

constexpr const char* kScenario = R"({"name": "plugged", "duration": 0.5,
 "controller": {"type": "plugin", "plugin": "example/sine", "genome_length": 2,
                "params": {"motors": ["Right/HipPitch", "Left/HipPitch"]}},
 "fitness": {"terms": [{"type": "plugin", "name": "head", "plugin": "example/mean_height",
                        "params": {"body": "Middle/Head"}}]}})";

class PluginJobsTest : public ::testing::Test {
 protected:
  // A broker; its client and worker endpoints.
  void StartBroker() {
    broker_.emplace(std::vector<std::string>{kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0",
                                             "--heartbeat", "0.1"});
    const std::optional<std::string> endpoints = broker_->ReadLine(milliseconds(10000));
    ASSERT_TRUE(endpoints.has_value()) << broker_->err();
    std::smatch match;
    ASSERT_TRUE(std::regex_match(*endpoints, match, std::regex("orcs-broker clients=(\\S+) workers=(\\S+)")));
    clients_ = match[1];
    workers_ = match[2];
  }
  // orcs-batch submit of `jobs` jobs of `scenario`; the results, one JSON object each.
  std::vector<nlohmann::json> Submit(const std::string& name, int jobs, const std::string& scenario = kScenario) {
    const std::string out = dir_.PathOf(name);
    const ProcessResult result = RunProcess({kBin + "orcs-batch", "submit", "--broker", clients_, "--heartbeat", "0.1",
                                             dir_.Write(name + ".json", scenario), "--genome", "[10, 1]", "--jobs",
                                             std::to_string(jobs), "--out", out, "--quiet"});
    EXPECT_NE(result.exit_code, 2) << result.err;  // not refused as bad input: the client cannot know the workers
    std::vector<nlohmann::json> lines;
    std::istringstream in(dir_.Read(out + "/results.jsonl"));
    for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
    return lines;
  }
  TempDir dir_;
  std::optional<BackgroundProcess> broker_;
  std::string clients_, workers_;
};

TEST_F(PluginJobsTest, AWorkerWithThePluginRunsItsJobsAndOneWithoutRefusesThem) {
  StartBroker();
  {
    BackgroundProcess worker({kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", "plugged",
                              "--plugins", kPlugins});
    const std::vector<nlohmann::json> results = Submit("with", 2);
    ASSERT_EQ(results.size(), 2u);
    for (const nlohmann::json& result : results) {
      ASSERT_EQ(result["status"], "ok") << result.dump();
      EXPECT_EQ(result["worker"], "plugged");
      const double head = result["terms"]["head"];
      EXPECT_GT(head, 0.3);  // the head of a standing A-Series, rocking a little: about 0.4 m up
      EXPECT_LT(head, 0.45);
    }
    EXPECT_THAT(worker.err(), HasSubstr("plug-ins from " + kPlugins + ": example/mean_height example/pd example/sine"));
  }
  BackgroundProcess bare({kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", "bare"});
  const std::vector<nlohmann::json> results = Submit("without", 1);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0]["status"], "plugin_missing");
  EXPECT_EQ(results[0]["worker"], "bare");
  EXPECT_THAT(results[0]["message"].get<std::string>(),
              AllOf(HasSubstr("plug-in controller 'example/sine'"), HasSubstr("no plug-ins")));
}

// The example's motor model in place of the Dynamixel model: with its gain at 0 the hips ask for 10° and do not move;
// with a gain they follow. A scripted term measures the hip's largest angle (scripts and plug-ins in one job).
TEST_F(PluginJobsTest, APluginMotorModelDrivesTheJoints) {
  StartBroker();
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", workers_, "--heartbeat", "0.1", "--id", "plugged",
                            "--plugins", kPlugins});
  const auto largest_hip_angle = [&](double gain) {
    nlohmann::json scenario = nlohmann::json::parse(kScenario);
    scenario["motor_model"] = {{"plugin", "example/pd"}, {"params", {{"gain", gain}}}};
    scenario["fitness"]["terms"] = {{{"type", "script"}, {"name", "hip"},
                                     {"script", {{"text", "local m = 0\nfunction step() m = math.max(m, math.abs("
                                                          "orcs.angle('Right/HipPitch'))) end\nfunction finish() "
                                                          "return m end"}}}}};
    const std::vector<nlohmann::json> results = Submit("pd-" + std::to_string(static_cast<int>(gain)), 1, scenario.dump());
    EXPECT_EQ(results.at(0)["status"], "ok") << results.at(0).dump();
    return results.at(0)["fitness"].get<double>();
  };
  EXPECT_LT(largest_hip_angle(0), 0.5);  // degrees: held where it stood
  EXPECT_GT(largest_hip_angle(20), 5);   // the sine of 10° at 1 Hz, followed
}

TEST_F(PluginJobsTest, ABadPluginFolderStopsTheWorkerAtItsStart) {
  const ProcessResult missing =
      RunProcess({kBin + "orcs-worker", "--connect", "tcp://127.0.0.1:9", "--plugins", dir_.PathOf("nowhere")});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.err, HasSubstr("--plugins: expected a folder"));
  dir_.Write("bad/libbroken.so", "not a shared library");
  const ProcessResult broken =
      RunProcess({kBin + "orcs-worker", "--connect", "tcp://127.0.0.1:9", "--plugins", dir_.PathOf("bad")});
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_THAT(broken.err, AllOf(HasSubstr("libbroken.so: cannot be loaded"), HasSubstr("orcs-worker: ")));
  EXPECT_EQ(std::count(broken.err.begin(), broken.err.end(), '\n'), 1) << broken.err;
}

}  // namespace
}  // namespace orcs
