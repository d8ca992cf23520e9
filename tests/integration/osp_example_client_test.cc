// scripts/osp_example_client.py, the protocol's living document, against a real orcs-osp: it must connect, list
// the agent, step it 200 times with a sine on one joint (which follows), read the observed value, and reset.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>

#include "tests/support/background_process.h"
#include "tests/support/process.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;
using ::testing::HasSubstr;

TEST(OspExampleClientTest, StepsASineOnOneJointAndResets) {
  test_support::BackgroundProcess server({ORCS_BINARY_DIR "/bin/orcs-osp", "-port", "0", "-odcp_port", "0"});
  const std::optional<std::string> line = server.ReadLine(milliseconds(10000));
  std::smatch match;
  ASSERT_TRUE(line && std::regex_match(*line, match, std::regex("orcs-osp osp=127\\.0\\.0\\.1:(\\d+)")))
      << server.err();
  const test_support::ProcessResult client = test_support::RunProcess(
      {"/usr/bin/python3", ORCS_SOURCE_DIR "/scripts/osp_example_client.py", "--port", match[1].str()});
  ASSERT_EQ(client.exit_code, 0) << client.err << client.out;
  EXPECT_THAT(client.out, HasSubstr("agent 1: Humanoid (type Agent, available)"));
  EXPECT_THAT(client.out, HasSubstr("agent 1 (Humanoid): 42 inputs, 37 outputs"));
  EXPECT_THAT(client.out, HasSubstr("observing /Sim/Humanoid/Right/ShoulderYaw/JointAngle"));
  EXPECT_THAT(client.out, HasSubstr("steps: 200"));
  // The joint followed the ±30° sine.
  std::smatch range;
  ASSERT_TRUE(std::regex_search(client.out, range, std::regex("JointAngle ranged from (-?[0-9.]+) to (-?[0-9.]+) deg")))
      << client.out;
  EXPECT_LT(std::stod(range[1]), -20.0);
  EXPECT_GT(std::stod(range[2]), 20.0);
  // The value read by id is the step reply's output (a float of the same double).
  std::smatch gap;
  ASSERT_TRUE(std::regex_search(client.out, gap, std::regex("observed value: ([0-9.]+) deg")));
  EXPECT_LT(std::stod(gap[1]), 1e-4);
  // After the reset the arm is back where it started.
  std::smatch reset;
  ASSERT_TRUE(std::regex_search(client.out, reset, std::regex("reset with seed 1: \\S+ = (-?[0-9.]+) deg")));
  EXPECT_LT(std::abs(std::stod(reset[1])), 1.0);
  EXPECT_THAT(client.out, HasSubstr("session ended"));
}

}  // namespace
}  // namespace orcs
