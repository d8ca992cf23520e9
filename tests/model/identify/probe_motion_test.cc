// The probe motions that tell two effects apart (model/identify/probe_motion.h): every probe of a motor stays within
// its stops, moves only that motor, and becomes a measured run its replay can play — on the pendulum rig and on an
// A-Series joint whose stops leave little room on one side.
#include "model/identify/probe_motion.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "model/aseries/value_range.h"
#include "model/identify/measured_run.h"
#include "tests/support/input_error_of.h"

namespace orcs::identify {
namespace {

using ::testing::HasSubstr;

TEST(ProbeMotionTest, EveryProbeStaysWithinTheMotorsStopsAndMovesIt) {
  for (const auto& [kind, motor] : {std::pair<std::string, std::string>{"pendulum", "Motor"},
                                    std::pair<std::string, std::string>{"aseries", "Right/Knee"}}) {
    SCOPED_TRACE(kind + " " + motor);
    RigOptions options;
    options.kind = kind;
    const Rig rig = MakeRig(options, kind == "pendulum" ? "Pendulum" : "Humanoid", {});
    const std::size_t index = static_cast<std::size_t>(
        std::find(rig.motors.begin(), rig.motors.end(), motor) - rig.motors.begin());
    const auto [lower, upper] = rig.motor_ranges.at(index);
    const std::vector<ProbeMotion> probes = ProbeMotions(rig, motor);
    ASSERT_EQ(probes.size(), ProbeNames().size());
    for (std::size_t p = 0; p < probes.size(); ++p) {
      const ProbeMotion& probe = probes[p];
      SCOPED_TRACE(probe.name);
      EXPECT_EQ(probe.name, ProbeNames()[p]);
      EXPECT_FALSE(probe.description.empty());
      EXPECT_FALSE(probe.shows.empty());
      ASSERT_EQ(probe.angle.size(), probe.torque.size());
      EXPECT_GT(probe.angle.size(), 300u);  // several seconds at the rig's step
      const auto [low, high] = std::minmax_element(probe.angle.begin(), probe.angle.end());
      EXPECT_GE(*low, lower);
      EXPECT_LE(*high, upper);
      EXPECT_GT(*high - *low, 4.0) << "a probe moves its motor";
      for (double torque : probe.torque) {
        EXPECT_GE(torque, 0.0);
        EXPECT_LE(torque, 1.0);
      }
    }
  }
}

TEST(ProbeMotionTest, AProbeRunCommandsEveryMotorAndReplaysAsAMeasuredRun) {
  RigOptions options;
  options.kind = "aseries";
  const Rig rig = MakeRig(options, "Humanoid", {});
  const ProbeMotion probe = FindProbe(rig, "Left/Elbow", "fast_steps");
  const MeasuredRun run = ProbeRun(rig, probe, nullptr);
  EXPECT_EQ(run.agent, "Humanoid");
  EXPECT_EQ(run.motors, rig.motors);
  ASSERT_EQ(run.time.size(), probe.angle.size() + 1);
  EXPECT_DOUBLE_EQ(run.time[1], rig.step);
  EXPECT_EQ(run.desired_angle.at("Left/Elbow")[5], probe.angle[4]);
  EXPECT_EQ(run.desired_angle.at("Right/Knee")[5], 0.0);
  EXPECT_EQ(run.desired_torque.at("Right/Knee")[5], aseries::kDefaultDesiredTorqueRaw);
  const ReplayRun replay = MakeReplayRun(rig, run, {});
  EXPECT_EQ(replay.channels.size(), rig.motors.size());
  // As a keyframe record for the robot: one row per step after the first, every motor's angle and torque.
  const control::KeyframeRecord record = CommandsAsRecord(run, rig.motors);
  EXPECT_EQ(record.frames.size(), probe.angle.size());
  EXPECT_EQ(record.frames.front().inputs.size(), 2 * rig.motors.size());
}

TEST(ProbeMotionTest, AnUnknownProbeOrMotorIsOneLineListingWhatThereIs) {
  RigOptions options;
  options.kind = "pendulum";
  const Rig rig = MakeRig(options, "Pendulum", {});
  EXPECT_THAT(test_support::InputErrorOf([&] { FindProbe(rig, "Motor", "wiggle"); }),
              HasSubstr("--probe: no probe motion 'wiggle' (known: slow_reversals, speed_ladder, loaded_lowering"));
  EXPECT_THAT(test_support::InputErrorOf([&] { FindProbe(rig, "Elbow", "fast_steps"); }),
              HasSubstr("--probe-motor: agent 'Pendulum' of (pendulum rig) has no motor 'Elbow'"));
}

}  // namespace
}  // namespace orcs::identify
