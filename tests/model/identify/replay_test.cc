// The replay job of a measured run (model/identify/replay.h): the run's inputs — its firmware gain and its
// winding temperature — are values of its replay after the model's, and its supply voltage a schedule of it, so
// one fitted model serves every run.
#include "model/identify/replay.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "model/core/error.h"
#include "model/core/value_file.h"
#include "model/identify/measured_run.h"
#include "model/scene/scenario.h"

namespace orcs::identify {
namespace {

constexpr const char* kXl330Model = ORCS_SOURCE_DIR "/scenarios/gap/xl330/model.val";

// Two rows of an XL330 log (scenarios/data/xl330-pendulum), the second one warmer and on a sagging supply.
constexpr const char* kLog =
    "# XL330 pendulum log: motor=xl330 firmware_kp=400\n"
    "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n"
    "0,0,0,0,0,7.4,31,1\n"
    "0.005,1,0,0,0,6.2,32,1\n";

ColumnMapping Mapping(bool with_temperature, bool with_voltage = false) {
  ColumnMapping mapping;
  mapping.source = "m.json";
  mapping.agent = "Pendulum";
  mapping.time.column = "time_s";
  ChannelMapping motor;
  motor.motor = "Motor";
  motor.desired_angle.emplace().column = "goal_deg";
  motor.desired_torque.emplace().column = "torque_enable";
  motor.joint_angle.emplace().column = "position_deg";
  mapping.channels.push_back(motor);
  mapping.firmware_kp.emplace().header = "firmware_kp";
  if (with_temperature) mapping.winding_temperature.emplace().column = "temperature_c";
  if (with_voltage) mapping.supply_voltage.emplace().column = "input_volts";
  return mapping;
}

TEST(ReplayTest, TheRunsGainAndMeanWindingTemperatureAreValuesOfItsReplay) {
  const std::vector<ValueAssignment> model = ValueFile::Read(kXl330Model);
  RigOptions options;
  options.kind = "pendulum";
  const Rig rig = MakeRig(options, "Pendulum", model);
  const ColumnMapping with = Mapping(true);
  const MeasuredRun warm = ParseMeasuredRun(kLog, "kp400.csv", &with);
  const ReplayRun replay = MakeReplayRun(rig, warm, model);
  const nlohmann::json& values = replay.scenario.at("values");
  EXPECT_EQ(values.at("/Servo/FirmwareKp"), "400");
  EXPECT_EQ(values.at("/Servo/WindingTemperature"), "31.5");
  const ColumnMapping without = Mapping(false);
  const MeasuredRun unmapped = ParseMeasuredRun(kLog, "kp400.csv", &without);
  const ReplayRun model_temperature = MakeReplayRun(rig, unmapped, model);
  EXPECT_FALSE(model_temperature.scenario.at("values").contains("/Servo/WindingTemperature"))
      << "no temperature in the data: the model's";
}

// A run's supply voltage is a schedule of its replay (docs/gap_measured_data.md, "The supply voltage"): each row's
// voltage during the step that ends at that row, timed as that row's commands, one entry per row after the first,
// in a form the scenario reader accepts; a run without a mapped voltage has no schedule and runs on the model's
// constant /Servo/SupplyVoltage.
TEST(ReplayTest, TheRunsSupplyVoltageIsScheduledRowByRowInItsReplay) {
  const std::vector<ValueAssignment> model = ValueFile::Read(kXl330Model);
  RigOptions options;
  options.kind = "pendulum";
  const Rig rig = MakeRig(options, "Pendulum", model);
  const ColumnMapping with = Mapping(false, true);
  const MeasuredRun run = ParseMeasuredRun(kLog, "kp400.csv", &with);
  const ReplayRun replay = MakeReplayRun(rig, run, model);
  const nlohmann::json& schedule = replay.scenario.at("schedules").at("/Servo/SupplyVoltage");
  // Row 1's voltage holds during the step that ends at row 1, as row 1's commands do (its keyframe's time).
  EXPECT_EQ(schedule.at("times"), nlohmann::json({0.0}));
  EXPECT_EQ(schedule.at("values"), nlohmann::json({6.2}));
  const control::KeyframeRecord commands = CommandsAsRecord(run, rig.motors);
  ASSERT_EQ(commands.frames.size(), 1u);
  EXPECT_EQ(commands.frames[0].time_ms, 1000.0 * schedule.at("times")[0].get<double>());
  EXPECT_EQ(replay.scenario.at("schedules").size(), 1u);

  const scene::Scenario scenario = scene::ParseScenario(replay.scenario, "kp400.json");
  ASSERT_EQ(scenario.schedules.size(), 1u);
  EXPECT_EQ(scenario.schedules[0].path, "/Servo/SupplyVoltage");
  EXPECT_EQ(scenario.schedules[0].times.size(), run.time.size() - 1);
  EXPECT_EQ(scenario.schedules[0].values, std::vector<double>(run.supply_voltage.begin() + 1, run.supply_voltage.end()));

  const ColumnMapping without = Mapping(false);
  const ReplayRun constant = MakeReplayRun(rig, ParseMeasuredRun(kLog, "kp400.csv", &without), model);
  EXPECT_FALSE(constant.scenario.contains("schedules")) << "no voltage in the data: the model's";
}

// A servo whose firmware runs faster than its log is replayed with sub-steps: each logged row is one simulation
// step of IterationsPerStep physics steps, the row's goal held through them.
TEST(ReplayTest, ARowIsTheStepTimesItsIterationsSoSubStepsReplayTheLogsTimeBase) {
  std::vector<ValueAssignment> model = ValueFile::Read(kXl330Model);
  model.push_back({"/Simulation/TimeStepSize", "0.001", "sub-steps", 0});
  RigOptions options;
  options.kind = "pendulum";
  const ColumnMapping mapping = Mapping(false);
  const MeasuredRun run = ParseMeasuredRun(kLog, "kp400.csv", &mapping);
  try {
    MakeReplayRun(MakeRig(options, "Pendulum", model), run, model);
    ADD_FAILURE() << "1 ms steps replayed a log of 5 ms rows";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("steps of 0.005 s, but the rig simulates steps of 0.001 s "
                                         "(/Simulation/TimeStepSize × /Simulation/IterationsPerStep)"),
              std::string::npos)
        << e.what();
    // It says what to change (issue 52's paper cut) — and what it says works, below.
    EXPECT_NE(std::string(e.what()).find("a --model value file with /Simulation/IterationsPerStep=5"), std::string::npos)
        << e.what();
  }
  model.push_back({"/Simulation/IterationsPerStep", "5", "sub-steps", 0});
  const Rig rig = MakeRig(options, "Pendulum", model);
  EXPECT_DOUBLE_EQ(rig.step, 0.005);
  EXPECT_NO_THROW(MakeReplayRun(rig, run, model));
}

// A newcomer's paper cuts (issue 52): a motor name that is not the rig's lists the near ones, and pendulum runs on
// the default rig say to add --rig pendulum.
TEST(ReplayTest, AMismatchBetweenRunsAndRigSaysWhatToChange) {
  const std::vector<ValueAssignment> model;
  const Rig aseries = MakeRig(RigOptions{}, "Humanoid", model);
  const MeasuredRun hip = ParseMeasuredRun(
      "# columns: time,/Sim/Humanoid/Right/Hip/DesiredAngle,/Sim/Humanoid/Right/Hip/DesiredTorque,"
      "/Sim/Humanoid/Right/Hip/JointAngle\n0,0,1,0\n0.01,1,1,0.5\n",
      "hip.csv");
  try {
    MakeReplayRun(aseries, hip, model);
    ADD_FAILURE() << "a motor the A-Series lacks";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no motor 'Right/Hip' (did you mean 'Right/HipYaw', 'Right/HipRoll' or "
                                         "'Right/HipPitch'?)"),
              std::string::npos)
        << e.what();
  }
  try {
    MakeRig(RigOptions{}, "Pendulum", model);
    ADD_FAILURE() << "the default rig has no pendulum";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no agent 'Pendulum' (the runs' agent); the runs are a pendulum rig's: add "
                                         "--rig pendulum"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace orcs::identify
