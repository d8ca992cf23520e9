// orcs-robot, the real binary, on 21 emulated AX-12+ servos behind a real pseudo-terminal: a record played and
// logged as a measured run; and the safety rules — limits clamp before anything is sent, a servo alarm and Ctrl-C
// stop the run with the torque off, nothing moves without confirmation, a dry run sends nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <algorithm>
#include <fstream>
#include <utility>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "hardware/dynamixel/dynamixel_bus.h"
#include "hardware/emulator/servo_bus_emulator.h"
#include "hardware/robot/joint_map.h"
#include "hardware/robot/simulated_twin.h"
#include "model/evaluation/recording_reader.h"
#include "model/identify/measured_run.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/udp_peer.h"

namespace orcs::hardware {
namespace {

using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kRobot = ORCS_BINARY_DIR "/bin/orcs-robot";
const std::string kMap = ORCS_SOURCE_DIR "/scenarios/robots/aseries.joints.json";
constexpr int kJoints = 21;

std::vector<std::uint8_t> AllIds() {
  std::vector<std::uint8_t> ids;
  for (int id = 1; id <= kJoints; ++id) ids.push_back(static_cast<std::uint8_t>(id));
  return ids;
}

// A raw keyframe record for the 21 joints: every joint at 0° except the waist (joint 0) and the right elbow
// (joint 5), at the given angles per row, full torque; rows `step_ms` apart.
std::string Record(const std::vector<std::pair<double, double>>& waist_and_elbow, int step_ms) {
  std::string text = "# layout: raw\n";
  for (std::size_t row = 0; row < waist_and_elbow.size(); ++row) {
    text += std::to_string(static_cast<int>(row) * step_ms);
    for (int j = 0; j < kJoints; ++j) {
      const double angle = j == 0 ? waist_and_elbow[row].first : j == 5 ? waist_and_elbow[row].second : 0.0;
      text += "," + std::to_string(angle) + ",1";
    }
    text += "\n";
  }
  return text;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string Write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir.path() / name).string();
  std::ofstream(path) << text;
  return path;
}

// Waits, bounded, until the process's stderr holds `text`; false when it ends or the time is up first.
bool AwaitErr(BackgroundProcess& process, const std::string& text) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    if (process.err().find(text) != std::string::npos) return true;
    if (process.Wait(std::chrono::milliseconds(10))) return process.err().find(text) != std::string::npos;
  }
  return false;
}

// The goal-position writes the emulator applied to servo `id`, in ticks.
std::vector<std::int64_t> GoalWrites(const std::vector<AppliedWrite>& writes, std::uint8_t id) {
  std::vector<std::int64_t> goals;
  for (const AppliedWrite& w : writes) {
    if (w.id == id && w.address == dynamixel::kAx12.goal_position) goals.push_back(dynamixel::FromLittleEndian(w.bytes));
  }
  return goals;
}

// Waits, bounded, until the emulator has applied a goal write to servo `id` ("playing" is said before the first
// period's write reaches the bus); false when the process ends or the time is up first.
bool AwaitGoalWrite(BackgroundProcess& process, const ServoBusEmulator& emulator, std::uint8_t id) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!GoalWrites(emulator.writes(), id).empty()) return true;
    if (process.Wait(std::chrono::milliseconds(10))) return !GoalWrites(emulator.writes(), id).empty();
  }
  return false;
}

// The program has ended; its last packets (torque off) may still be in the terminal's buffer: awaited, bounded.
bool AllTorqueOff(const ServoBusEmulator& emulator) {
  return emulator.AwaitAllTorqueOff(std::chrono::seconds(10));
}

TEST(OrcsRobotTest, PlaysARecordOnTwentyOneServosAndLogsAMeasuredRunOrcsGapReads) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {20, -30}, {40, -60}, {40, -60}}, 200));
  const std::string log = (dir.path() / "run.csv").string();
  const std::string twin_log = (dir.path() / "twin.csv").string();
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--out", log,
                                      "--twin-out", twin_log, "--rate", "50", "--yes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("finished; torque off"));
  EXPECT_TRUE(AllTorqueOff(emulator));
  const identify::MeasuredRun run = identify::ReadMeasuredRun(log);
  EXPECT_EQ(run.agent, "Humanoid");
  EXPECT_EQ(run.motors.size(), 21u);
  EXPECT_EQ(run.commanded.size(), 21u);
  EXPECT_NEAR(run.step, 0.02, 1e-12);
  EXPECT_GE(run.time.back(), 0.6) << "the record lasts 0.6 s";
  // The emulated shafts followed: the waist reached 40°, the elbow −60°, each within a tick.
  EXPECT_NEAR(run.joint_angle.at("Waist").back(), 40.0, 0.3);
  EXPECT_NEAR(run.joint_angle.at("Right/Elbow").back(), -60.0, 0.3);
  EXPECT_NEAR(emulator.Angle(1), 40.0, 0.3);
  // The simulated twin got the same commands, period by period: same rows, same inputs, its own angles, and its
  // simulated A-Series follows them too (within its servo model's lag).
  const identify::MeasuredRun twin = identify::ReadMeasuredRun(twin_log);
  EXPECT_EQ(twin.time, run.time);
  EXPECT_EQ(twin.desired_angle, run.desired_angle);
  EXPECT_EQ(twin.desired_torque, run.desired_torque);
  EXPECT_NE(twin.joint_angle.at("Waist"), run.joint_angle.at("Waist")) << "the twin's angles are its own";
  EXPECT_NEAR(twin.joint_angle.at("Waist").back(), 40.0, 3.0);
  EXPECT_NEAR(twin.joint_angle.at("Right/Elbow").back(), -60.0, 3.0);
}

// --view: the folder orcs-view follows holds the robot as measured and its twin, period by period — the same
// angles as the two logs — and says how the run ended.
TEST(OrcsRobotTest, TheViewFolderRecordsTheRobotAndItsTwinPeriodByPeriod) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {20, -30}, {40, -60}, {40, -60}}, 200));
  const std::string log = (dir.path() / "run.csv").string();
  const std::string twin_log = (dir.path() / "twin.csv").string();
  const std::string view = (dir.path() / "view").string();
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play",
                                      record, "--out", log, "--twin-out", twin_log, "--view", view, "--yes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const identify::MeasuredRun run = identify::ReadMeasuredRun(log);
  const identify::MeasuredRun twin = identify::ReadMeasuredRun(twin_log);
  const evaluation::Recording robot_rec = evaluation::ReadRecording(view + "/robot.orcsrec");
  const evaluation::Recording twin_rec = evaluation::ReadRecording(view + "/twin.orcsrec");
  ASSERT_EQ(robot_rec.frame_count(), static_cast<int>(run.time.size())) << "a frame per control period";
  ASSERT_EQ(twin_rec.frame_count(), static_cast<int>(run.time.size()));
  const int robot_angle = robot_rec.FindChannel("/Sim/Humanoid/Right/Elbow/JointAngle");
  const int robot_goal = robot_rec.FindChannel("/Sim/Humanoid/Right/Elbow/DesiredAngle");
  const int twin_angle = twin_rec.FindChannel("/Sim/Humanoid/Right/Elbow/JointAngle");
  ASSERT_GE(robot_angle, 0);
  ASSERT_GE(robot_goal, 0);
  ASSERT_GE(twin_angle, 0);
  for (int f = 0; f < robot_rec.frame_count(); ++f) {
    const auto row = static_cast<std::size_t>(f);
    EXPECT_NEAR(robot_rec.times[row], run.time[row], 1e-9);
    EXPECT_NEAR(robot_rec.value(f, robot_angle), run.joint_angle.at("Right/Elbow")[row], 1e-3) << "measured, frame " << f;
    EXPECT_NEAR(robot_rec.value(f, robot_goal), run.desired_angle.at("Right/Elbow")[row], 1e-3) << "command, frame " << f;
    EXPECT_NEAR(twin_rec.value(f, twin_angle), twin.joint_angle.at("Right/Elbow")[row], 1e-3) << "twin, frame " << f;
  }
  // The last frame holds where the record left the elbow.
  EXPECT_NEAR(robot_rec.value(robot_rec.frame_count() - 1, robot_angle), -60.0, 0.5);
  const nlohmann::json progress = nlohmann::json::parse(ReadFile(view + "/progress.json"));
  EXPECT_EQ(progress["command"], "robot");
  EXPECT_EQ(progress["state"], "finished");
  EXPECT_EQ(progress["periods"], run.time.size());
  const nlohmann::json about = nlohmann::json::parse(ReadFile(view + "/robot_run.json"));
  EXPECT_EQ(about["played"], record);
  EXPECT_EQ(about["joints"].size(), 21u);
}

// A real servo reads a hair past the model's hinge stop now and then (the emulator's delayed waist, resting at its
// 0° stop, read −0.3°): posing the twin or the robot's model there must not break the model's invariant (it aborted
// orcs-robot --view once ORCS_DEMAND stayed on); the pose is the stop.
TEST(SimulatedTwinTest, AMeasuredAngleAHairPastAStopIsPosedAtTheStop) {
  const JointMap map = ReadJointMap(kMap);
  SimulatedTwin twin("", map);
  std::vector<double> angles(map.joints.size(), 0.0);
  angles[0] = -0.3;  // the waist's stop is 0°
  twin.StartAt(angles);
  twin.Pose(angles, angles);
  const std::vector<double> after = twin.Angles();
  EXPECT_DOUBLE_EQ(after[0], -0.3) << "the sensors read what was measured";
  twin.Advance(std::vector<double>(map.joints.size(), 0.0), std::vector<double>(map.joints.size(), 1.0), 0.02);
  EXPECT_EQ(twin.status(), "") << "and the twin runs on from the stop";
}

TEST(OrcsRobotTest, ACommandBeyondAJointsLimitIsClampedAndNothingPastItIsSent) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  // The waist may bend 0…150° (spec/aseries.md §4c): 170° and −20° are beyond its two limits.
  const std::string record = Write(dir, "beyond.csv", Record({{0, 0}, {170, 0}, {-20, 0}}, 100));
  const ProcessResult r =
      RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--rate", "50", "--yes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, Not(HasSubstr(" 0 commands clamped")));
  const JointMap map = ReadJointMap(kMap);
  const std::int64_t upper = std::min<std::int64_t>(ToTicks(*map.Find("Waist"), 150.0), dynamixel::kAx12.max_tick);
  const std::int64_t lower = ToTicks(*map.Find("Waist"), 0.0);
  const std::vector<std::int64_t> goals = GoalWrites(emulator.writes(), 1);
  ASSERT_FALSE(goals.empty());
  EXPECT_EQ(*std::max_element(goals.begin(), goals.end()), std::max(upper, lower)) << "held at the limit (150° is "
                                                                                      "tick 1024, past the AX-12's "
                                                                                      "last tick 1023)";
  EXPECT_EQ(*std::min_element(goals.begin(), goals.end()), std::min(upper, lower)) << "held at the other";
}

TEST(OrcsRobotTest, AServoAlarmStopsTheRunWithTheTorqueOffAndSaysWhy) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "long.csv", Record({{0, 0}, {30, 0}, {60, 0}}, 5000));
  BackgroundProcess robot({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--yes"});
  ASSERT_TRUE(AwaitErr(robot, "playing")) << robot.err();
  ASSERT_TRUE(emulator.TorqueOn(14));
  emulator.RaiseAlarm(14, dynamixel::protocol1::kOverloadError);
  const std::optional<ProcessResult> r = robot.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(r.has_value()) << "the run must stop";
  EXPECT_EQ(r->exit_code, 1);
  EXPECT_THAT(r->err, HasSubstr("stopped: servo 14 reports overload"));
  EXPECT_THAT(r->err, HasSubstr("torque off"));
  EXPECT_TRUE(AllTorqueOff(emulator));
}

TEST(OrcsRobotTest, CtrlCTurnsTheTorqueOffWithinOneControlPeriod) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "long.csv", Record({{0, 0}, {30, 0}, {60, 0}}, 5000));
  BackgroundProcess robot({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--yes"}, true);
  ASSERT_TRUE(AwaitErr(robot, "playing")) << robot.err();
  ASSERT_TRUE(AwaitGoalWrite(robot, emulator, 1)) << "it has been sending goals\n" << robot.err();
  const std::size_t goals_before = GoalWrites(emulator.writes(), 1).size();
  robot.SignalGroup(SIGINT);
  const std::optional<ProcessResult> r = robot.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->exit_code, 130) << r->err;
  EXPECT_THAT(r->err, HasSubstr("stopped: interrupted"));
  EXPECT_TRUE(AllTorqueOff(emulator));
  // Within one control period: at most the goal already on its way when the signal came, then torque off.
  EXPECT_LE(GoalWrites(emulator.writes(), 1).size(), goals_before + 1);
  EXPECT_EQ(emulator.writes().back().address, dynamixel::kAx12.torque_enable);
}

TEST(OrcsRobotTest, NothingMovesUntilTheFirstPoseIsConfirmed) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {20, 0}}, 100));
  // stdin is /dev/null: no answer, so no.
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("the first pose moves 21 joints"));
  EXPECT_THAT(r.err, HasSubstr("not confirmed: nothing was sent (pass --yes"));
  EXPECT_TRUE(emulator.writes().empty()) << "not a byte of the control tables written";
}

TEST(OrcsRobotTest, ADryRunPrintsThePacketsAndOpensNoPort) {
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {170, 0}}, 100));
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--play", record, "--dry-run", "--rate", "20"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("SYNC_WRITE torque enable: every joint = 1"));
  EXPECT_THAT(r.out, HasSubstr("SYNC_WRITE goal position: Waist(1)="));
  EXPECT_THAT(r.out, HasSubstr("SYNC_WRITE torque enable: every joint = 0"));
  EXPECT_THAT(r.err, HasSubstr("dry run: nothing is sent"));
}

TEST(OrcsRobotTest, AMissingServoIsNamedBeforeAnythingIsSent) {
  std::vector<std::uint8_t> ids = AllIds();
  ids.erase(ids.begin() + 6);  // servo 7 (Left/Elbow) unplugged
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, ids, 684.0));
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {20, 0}}, 100));
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--yes"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("servo 7 (Left/Elbow) did not answer"));
  EXPECT_THAT(r.err, HasSubstr("baud rate"));
  EXPECT_TRUE(emulator.writes().empty());
}

TEST(OrcsRobotTest, TheXl330PendulumPlaysInProtocol2OnEmulatedServosWithItsTwin) {
  TempDir dir;
  const std::string record = Write(dir, "swing.csv", "# layout: raw\n0,0,1\n200,30,1\n400,-30,1\n1500,-30,1\n");
  const std::string log = (dir.path() / "run.csv").string();
  const std::string twin_log = (dir.path() / "twin.csv").string();
  const std::string bam_log = (dir.path() / "run.json").string();
  const ProcessResult r = RunProcess({kRobot, "--map", ORCS_SOURCE_DIR "/scenarios/robots/pendulum_xl330.joints.json",
                                      "--play", record, "--emulate", "--yes", "--rate", "100", "--out", log,
                                      "--twin-out", twin_log, "--twin-env",
                                      ORCS_SOURCE_DIR "/scenarios/environments/pendulum.xml", "--bam-out", bam_log,
                                      "--bam-kp", "32"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("on 1 XL330-M288"));
  const identify::MeasuredRun run = identify::ReadMeasuredRun(log);
  const identify::MeasuredRun twin = identify::ReadMeasuredRun(twin_log);
  EXPECT_EQ(run.agent, "Pendulum");
  EXPECT_NEAR(run.joint_angle.at("Motor").back(), -30.0, 0.1) << "4096 ticks per turn: a tick is 0.088°";
  EXPECT_NEAR(twin.joint_angle.at("Motor").back(), -30.0, 3.0);
  // The same run in BAM's format reads back (BAM's timing, radians) as the orcs log does.
  const identify::MeasuredRun bam = identify::ReadMeasuredRun(bam_log);
  EXPECT_EQ(bam.time, run.time);
  EXPECT_EQ(identify::FirmwareGain(bam), 32.0);
  ASSERT_EQ(bam.joint_angle.at("Motor").size(), run.joint_angle.at("Motor").size());
  for (std::size_t k = 0; k < run.time.size(); ++k) {
    EXPECT_NEAR(bam.joint_angle.at("Motor")[k], run.joint_angle.at("Motor")[k], 1e-9) << "row " << k;
    if (k > 0) {  // row 0's inputs are never applied; BAM's timing leaves it its own goal
      EXPECT_NEAR(bam.desired_angle.at("Motor")[k], run.desired_angle.at("Motor")[k], 1e-9) << "row " << k;
    }
  }
}

// Runs a scenario's controller on 21 emulated AX-12+ and its twin; returns the robot's and the twin's logs.
std::pair<identify::MeasuredRun, identify::MeasuredRun> RunController(const std::vector<std::string>& controller) {
  TempDir dir;
  const std::string log = (dir.path() / "run.csv").string();
  const std::string twin_log = (dir.path() / "twin.csv").string();
  std::vector<std::string> argv{kRobot, "--map", kMap, "--emulate", "--yes", "--out", log, "--twin-out", twin_log};
  argv.insert(argv.end(), controller.begin(), controller.end());
  const ProcessResult r = RunProcess(argv);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return {identify::ReadMeasuredRun(log), identify::ReadMeasuredRun(twin_log)};
}

TEST(OrcsRobotTest, AnOscillatorDrivesTheRobotAndItsTwinWithTheSameCommands) {
  const auto [robot, twin] = RunController(
      {"--scenario", ORCS_SOURCE_DIR "/scenarios/examples/swing_oscillator.json", "--duration", "1.2"});
  const std::vector<double>& goal = robot.desired_angle.at("Right/HipYaw");
  EXPECT_GT(*std::max_element(goal.begin(), goal.end()), 8.0) << "the oscillator's amplitude is 10°";
  EXPECT_LT(*std::min_element(goal.begin(), goal.end()), -8.0);
  EXPECT_EQ(twin.desired_angle, robot.desired_angle);
  EXPECT_NEAR(robot.joint_angle.at("Right/HipYaw")[40], goal[40], 1.0) << "the emulated servo follows";
}

TEST(OrcsRobotTest, AnEvolvedGenomeRunsOnTheRobotAndItsTwinWithTheSameCommands) {
  const auto [robot, twin] = RunController(
      {"--scenario", ORCS_SOURCE_DIR "/scenarios/evolution/rock_oscillator.json", "--genome",
       ORCS_SOURCE_DIR "/scenarios/evolution/rock_oscillator.winner.json", "--duration", "1"});
  EXPECT_EQ(robot.time.size(), 52u) << "1 s at 50 Hz and the last state";
  EXPECT_EQ(twin.desired_angle, robot.desired_angle);
  // The network's outputs move: some joint's command changes over the run.
  bool moved = false;
  for (const auto& [joint, goal] : robot.desired_angle) {
    moved = moved || *std::max_element(goal.begin() + 1, goal.end()) - *std::min_element(goal.begin() + 1, goal.end()) > 1.0;
  }
  EXPECT_TRUE(moved);
}

TEST(OrcsRobotTest, BamsFormatIsRefusedForAManyJointMapBeforeAnythingMoves) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string record = Write(dir, "bend.csv", Record({{0, 0}, {20, 0}}, 100));
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--play", record, "--yes",
                                      "--bam-out", (dir.path() / "run.json").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("BAM's log format holds one servo; this map has 21 joints"));
  EXPECT_TRUE(emulator.writes().empty());
}


// ---- A motion editor's ODCP 1.0 (docs/spec/osp.md), spoken from the spec alone: int32 little-endian words,
// w ↔ n = −1 + 2w/1023, angle 150·n degrees, torque w/1023. ----
using Bytes = std::vector<std::uint8_t>;

std::int32_t AngleWord(double degrees) { return static_cast<std::int32_t>(std::lround((degrees / 150.0 + 1.0) * 511.5)); }
double AngleOfWord(std::int32_t word) { return 150.0 * (-1.0 + 2.0 * word / 1023.0); }

Bytes Message(std::uint8_t code, const std::vector<std::int32_t>& ints = {}) {
  Bytes bytes{code};
  for (std::int32_t v : ints) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(v) >> (8 * i)));
  }
  return bytes;
}

class Editor {
 public:
  explicit Editor(std::uint16_t port) : port_(port) {}
  bool Connect() { return Ask(Message(5)) == Message(6, {15, 1}); }
  bool Disconnect() { return Ask(Message(7)) == Message(8); }
  // Every joint at 0° except those given, full torque.
  void Set(const std::vector<std::pair<int, double>>& angles) {
    std::vector<std::int32_t> words(kJoints, AngleWord(0.0));
    for (const auto& [joint, degrees] : angles) words[static_cast<std::size_t>(joint)] = AngleWord(degrees);
    words.resize(2 * kJoints, 1023);
    peer_.SendTo(port_, Message(100, words));
  }
  // The angles get-motors reports, degrees; empty when no intact answer came.
  std::vector<double> Angles() {
    const std::optional<Bytes> reply = Ask(Message(150));
    std::vector<double> angles;
    if (!reply || reply->size() != 1 + 8 * kJoints || reply->front() != 151) return angles;
    for (int j = 0; j < kJoints; ++j) {
      std::uint32_t word = 0;
      for (int i = 3; i >= 0; --i) word = (word << 8) | (*reply)[1 + 4 * static_cast<std::size_t>(j) + static_cast<std::size_t>(i)];
      angles.push_back(AngleOfWord(static_cast<std::int32_t>(word)));
    }
    return angles;
  }

 private:
  std::optional<Bytes> Ask(const Bytes& bytes) {
    peer_.SendTo(port_, bytes);
    return peer_.Receive(std::chrono::milliseconds(5000));
  }
  std::uint16_t port_;
  test_support::UdpPeer peer_;
};

// The port of a "PROGRAM odcp=127.0.0.1:PORT" line; 0 when the line is not one.
std::uint16_t OdcpPort(const std::optional<std::string>& line, const std::string& program) {
  std::smatch match;
  if (!line || !std::regex_match(*line, match, std::regex(program + " odcp=127\\.0\\.0\\.1:(\\d+)"))) return 0;
  return static_cast<std::uint16_t>(std::stoi(match[1]));
}

constexpr int kWaist = 0;       // joint 0 of the map, servo 1
constexpr int kRightKnee = 13;  // joint 13, servo 14

TEST(OrcsRobotTest, AMotionEditorDrivesTheRobotOverOdcpWithinItsLimits) {
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  TempDir dir;
  const std::string log = (dir.path() / "edited.csv").string();
  BackgroundProcess robot({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250", "--odcp", "0",
                           "--yes", "--out", log});
  Editor editor(OdcpPort(robot.ReadLine(std::chrono::seconds(20)), "orcs-robot"));
  ASSERT_TRUE(editor.Connect()) << robot.err();
  // Get-motors answers the robot's measured angles: the emulated servos stand at their centre (0°).
  const std::vector<double> found = editor.Angles();
  ASSERT_EQ(found.size(), static_cast<std::size_t>(kJoints)) << robot.err();
  for (double angle : found) EXPECT_NEAR(angle, 0.0, 0.3);
  // The knee to 30°; the waist to 170°, beyond its 150° limit.
  editor.Set({{kRightKnee, 30.0}, {kWaist, 170.0}});
  std::vector<double> now;
  for (int ask = 0; ask < 500; ++ask) {  // one answer per control period (20 ms): 10 s at most
    now = editor.Angles();
    if (now.size() == found.size() && std::abs(now[kRightKnee] - 30.0) < 0.5 && now[kWaist] > 149.6) break;  // at rest
  }
  ASSERT_EQ(now.size(), found.size());
  EXPECT_NEAR(now[kRightKnee], 30.0, 0.5) << "the measured knee reached the editor's goal";
  EXPECT_NEAR(now[kWaist], 150.0, 0.5) << "the waist stopped at its limit";
  EXPECT_NEAR(emulator.Angle(14), 30.0, 0.5);
  ASSERT_TRUE(editor.Disconnect());
  const std::optional<ProcessResult> r = robot.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(r.has_value()) << "the editor's disconnect ends the session";
  EXPECT_EQ(r->exit_code, 0) << r->err;
  EXPECT_THAT(r->err, HasSubstr("the editor disconnected; torque off"));
  EXPECT_TRUE(AllTorqueOff(emulator));
  const std::vector<std::int64_t> waist_goals = GoalWrites(emulator.writes(), 1);
  ASSERT_FALSE(waist_goals.empty());
  EXPECT_LE(*std::max_element(waist_goals.begin(), waist_goals.end()), dynamixel::kAx12.max_tick)
      << "nothing past the limit was sent";
  // The session is a measured run: the editor's commands, clamped, beside the measured angles.
  const identify::MeasuredRun run = identify::ReadMeasuredRun(log);
  EXPECT_NEAR(run.desired_angle.at("Right/Knee").back(), AngleOfWord(AngleWord(30.0)), 1e-6);
  EXPECT_NEAR(run.desired_angle.at("Waist").back(), 150.0, 1e-9);
  EXPECT_NEAR(run.joint_angle.at("Right/Knee").back(), 30.0, 0.5);
}

TEST(OrcsRobotTest, AnOrcsSnifferRecordReplaysOnTheRobot) {
  TempDir dir;
  const std::string sniffed = (dir.path() / "sniffed.csv").string();
  {
    BackgroundProcess sniffer({ORCS_BINARY_DIR "/bin/orcs-sniffer", sniffed, "--port", "0"});
    Editor editor(OdcpPort(sniffer.ReadLine(std::chrono::seconds(20)), "orcs-sniffer"));
    ASSERT_TRUE(editor.Connect()) << sniffer.err();
    // The waist to 20°, then 40°, and the right knee to 30° with it, at the editor's own pace of 150 ms.
    const auto start = std::chrono::steady_clock::now();
    editor.Set({{kWaist, 0.0}});
    std::this_thread::sleep_until(start + std::chrono::milliseconds(150));
    editor.Set({{kWaist, 20.0}});
    std::this_thread::sleep_until(start + std::chrono::milliseconds(300));
    editor.Set({{kWaist, 40.0}, {kRightKnee, 30.0}});
    ASSERT_TRUE(editor.Disconnect());
    const std::optional<ProcessResult> recorded = sniffer.Wait(std::chrono::seconds(20));
    ASSERT_TRUE(recorded.has_value());
    ASSERT_EQ(recorded->exit_code, 0) << recorded->err;
  }
  ServoBusEmulator emulator(KinematicBus(dynamixel::kAx12, AllIds(), 684.0));
  const std::string log = (dir.path() / "replayed.csv").string();
  const ProcessResult r = RunProcess({kRobot, "--map", kMap, "--port", emulator.port(), "--timeout-ms", "250",
                                      "--play", sniffed, "--out", log, "--yes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(AllTorqueOff(emulator));
  // The servos got the editor's last pose, as goal ticks.
  const JointMap map = ReadJointMap(kMap);
  ASSERT_FALSE(GoalWrites(emulator.writes(), 1).empty());
  EXPECT_EQ(GoalWrites(emulator.writes(), 1).back(), ToTicks(*map.Find("Waist"), AngleOfWord(AngleWord(40.0))));
  EXPECT_EQ(GoalWrites(emulator.writes(), 14).back(), ToTicks(*map.Find("Right/Knee"), AngleOfWord(AngleWord(30.0))));
  const identify::MeasuredRun run = identify::ReadMeasuredRun(log);
  const std::vector<double>& waist = run.desired_angle.at("Waist");
  EXPECT_NE(std::find_if(waist.begin(), waist.end(), [](double a) { return std::abs(a - AngleOfWord(AngleWord(20.0))) < 1e-6; }),
            waist.end())
      << "the middle command was played too";
  EXPECT_NEAR(waist.back(), AngleOfWord(AngleWord(40.0)), 1e-6);
}

}  // namespace
}  // namespace orcs::hardware
