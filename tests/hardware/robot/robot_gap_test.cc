// The whole loop of issue 51 on any machine: orcs-robot records two motions through the Dynamixel bus of the
// servo-bus emulator, whose shafts are orcs's pendulum rig with a hidden 30 ms transport delay; orcs-gap on the
// recorded runs, read as they stand, names the delay and the fitted model tracks the emulated servo on the
// held-out motion.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs::hardware {
namespace {

using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::HasSubstr;

const std::string kRobot = ORCS_BINARY_DIR "/bin/orcs-robot";
const std::string kGap = ORCS_BINARY_DIR "/bin/orcs-gap";

// Records `motion` (scenarios/motions/) through the emulated bus into `log`.
void Record(const std::string& motion, const std::string& values, const std::string& log) {
  const ProcessResult r = RunProcess(
      {kRobot, "--map", ORCS_SOURCE_DIR "/scenarios/robots/pendulum_xl330.joints.json", "--play",
       ORCS_SOURCE_DIR "/scenarios/motions/" + motion + ".csv", "--emulate", "--emulate-env",
       ORCS_SOURCE_DIR "/scenarios/environments/pendulum.xml", "--emulate-val", values, "--unpaced", "--yes",
       "--rate", "100", "--out", log});
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

TEST(RobotGapTest, RunsRecordedThroughTheBusLetOrcsGapNameTheDelayTheEmulatorHid) {
  TempDir dir;
  const std::string values = (dir.path() / "hidden.val").string();
  std::ofstream(values) << "#ORCS Values\n/Effects/TransportDelay/Enabled=T\n/Effects/TransportDelay/Delay=0.03\n";
  const std::string fit = (dir.path() / "fit.csv").string();
  const std::string held_out = (dir.path() / "held_out.csv").string();
  Record("pendulum_identification_a", values, fit);
  Record("pendulum_identification_b", values, held_out);
  const std::string report = (dir.path() / "report").string();
  const ProcessResult gap = RunProcess({kGap, "--rig", "pendulum", "--measured", fit, "--holdout", held_out,
                                        "--workers", "2", "--out", report});
  ASSERT_EQ(gap.exit_code, 0) << gap.err;
  EXPECT_THAT(gap.out, HasSubstr("Missing effect: TransportDelay"));
  const nlohmann::json verdict = nlohmann::json::parse(std::ifstream(report + "/report.json"))["verdict"];
  EXPECT_EQ(verdict["effects"], nlohmann::json::array({"TransportDelay"})) << "named alone";
  EXPECT_LE(verdict["holdout_rms_after"].get<double>(), 0.5 * verdict["holdout_rms_refit"].get<double>())
      << "the held-out gap at least halved";
  std::ifstream model(report + "/model.val");
  std::string line, delay;
  while (std::getline(model, line)) {
    if (line.starts_with("/Effects/TransportDelay/Delay=")) delay = line.substr(line.find('=') + 1);
  }
  ASSERT_FALSE(delay.empty());
  EXPECT_NEAR(std::stod(delay), 0.03, 0.012) << "the hidden 30 ms, within a period and a fifth";
}

}  // namespace
}  // namespace orcs::hardware
