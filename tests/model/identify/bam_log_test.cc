#include "model/identify/bam_log.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "model/core/text.h"
#include "tests/support/input_error_of.h"

namespace orcs::identify {
namespace {

using test_support::InputErrorOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// Twelve rows of a real XL330 log (scenarios/data/xl330-pendulum/sin_time_square_kp400.csv, from t = 2.99 s,
// times counted from there), the last one limp: BAM's log converted to degrees.
constexpr const char* kXl330Csv =
    "# XL330 pendulum log: motor=xl330 load_mass_kg=0.49 load_distance_m=0.1 firmware_kp=400 supply_v=7.4 dt_s=0.005 "
    "trajectory=sin_time_square\n"
    "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n"
    "0,27.7541772,33.4320398,-83.0641624,65440.7646,7.3,34,1\n"
    "0.005,26.2383067,32.7240666,-90.5628411,65424.1764,7.3,34,1\n"
    "0.01,24.731478,32.1508902,-100.100135,65409.2701,7.3,34,1\n"
    "0.015,23.2538202,31.5933876,-106.314926,65395.0863,7.305,34,1\n"
    "0.02,21.6105483,30.8334148,-114.631419,65380.3868,7.392,34,1\n"
    "0.025,20.0676542,30.0740375,-122.941397,65364.9163,7.322,34,1\n"
    "0.03,18.4224215,29.1918964,-130.434569,65351.1736,7.3,34,1\n"
    "0.035,16.7423865,28.3068929,-139.20415,65337.913,7.408,34,1\n"
    "0.04,15.0527237,27.3562307,-149.129213,65323.9269,7.412,34,1\n"
    "0.045,13.3506564,26.3948581,-158.300054,65310.5778,7.263,34,1\n"
    "0.05,11.6475615,25.5161858,-166.035883,65299.6244,7.231,34,1\n"
    "0.055,9.9354624,24.463688,-174.76532,65288.5862,7.276,34,0\n";

double Radians(const std::string& degrees) { return std::stod(degrees) * std::numbers::pi / 180.0; }

// The log as BAM's recorder wrote it: the CSV's conversion undone (degrees back to radians), independently of
// the reader under test.
std::string AsBamLog(const std::string& csv) {
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // the rig's constants
  std::getline(lines, line);  // the header
  nlohmann::json log = {{"motor", "xl330"}, {"mass", 0.49}, {"length", 0.1}, {"kp", 400},
                        {"vin", 7.4},       {"dt", 0.005},  {"trajectory", "sin_time_square"}};
  log["entries"] = nlohmann::json::array();
  while (std::getline(lines, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) f.push_back(field);
    log["entries"].push_back({{"timestamp", std::stod(f[0])},
                              {"goal_position", Radians(f[1])},
                              {"position", Radians(f[2])},
                              {"speed", Radians(f[3])},
                              {"load", std::stod(f[4])},
                              {"input_volts", std::stod(f[5])},
                              {"temp", std::stod(f[6])},
                              {"torque_enable", f[7] == "1"}});
  }
  return log.dump();
}

TEST(BamLogTest, AnXl330LogInBamsFormatReadsAsItsCsvConversionBitForBit) {
  const ColumnMapping mapping = ReadColumnMapping(ORCS_SOURCE_DIR "/scenarios/gap/xl330/mapping.json");
  const MeasuredRun csv = ParseMeasuredRun(kXl330Csv, "run.csv", &mapping);
  const std::string bam_text = AsBamLog(kXl330Csv);
  ASSERT_TRUE(IsBamLog(bam_text));
  const MeasuredRun bam = ParseMeasuredRun(bam_text, "run.json", &mapping);
  EXPECT_EQ(bam.agent, csv.agent);
  EXPECT_EQ(bam.step, csv.step);
  EXPECT_EQ(bam.time, csv.time);
  EXPECT_EQ(bam.desired_angle, csv.desired_angle) << "goals: radians back to the CSV's degrees, to the bit";
  EXPECT_EQ(bam.joint_angle, csv.joint_angle);
  EXPECT_EQ(bam.desired_torque, csv.desired_torque);
  EXPECT_EQ(bam.firmware_kp, csv.firmware_kp) << "kp is the comment's firmware_kp";
  EXPECT_EQ(bam.supply_voltage, csv.supply_voltage);
  EXPECT_EQ(bam.command_timing, CommandTiming::kFromRow);
  EXPECT_EQ(bam.lines, csv.lines) << "row k's line is the same in the table as in the CSV";
}

TEST(BamLogTest, WithoutAMappingALogIsOnePendulumServoInDegreesWithBamsTiming) {
  const std::string log = R"({"kp": 32, "dt": 0.01, "entries": [
      {"timestamp": 5.0, "position": 0.0, "speed": 0, "load": 0, "input_volts": 12, "temp": 30,
       "goal_position": 0.5, "torque_enable": true},
      {"timestamp": 5.01, "position": 0.1, "speed": 0, "load": 0, "input_volts": 11.5, "temp": 30,
       "goal_position": 1.0, "torque_enable": true},
      {"timestamp": 5.02, "position": 0.2, "speed": 0, "load": 0, "input_volts": 11, "temp": 30,
       "goal_position": 1.5, "torque_enable": false}]})";
  const MeasuredRun run = ParseMeasuredRun(log, "bam.json", nullptr);
  EXPECT_EQ(run.agent, "Pendulum");
  EXPECT_THAT(run.motors, ElementsAre("Motor"));
  EXPECT_NEAR(run.step, 0.01, 1e-12) << "times count from the first timestamp";
  EXPECT_NEAR(run.time.back(), 0.02, 1e-12);
  EXPECT_NEAR(run.joint_angle.at("Motor")[2], 0.2 * 180 / std::numbers::pi, 1e-9) << "radians become degrees";
  // BAM reads the state, then sends the goal: row k's goal acts from t(k), so it moves to row k+1.
  EXPECT_NEAR(run.desired_angle.at("Motor")[1], 0.5 * 180 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(run.desired_angle.at("Motor")[2], 1.0 * 180 / std::numbers::pi, 1e-9);
  EXPECT_EQ(FirmwareGain(run), 32.0);
  EXPECT_THAT(run.supply_voltage, ElementsAre(12.0, 12.0, 11.5));
}

TEST(BamLogTest, ALogWithoutKpHasNoFirmwareGain) {
  const std::string log = R"({"entries": [
      {"timestamp": 0, "position": 0, "speed": 0, "load": 0, "input_volts": 7, "temp": 30, "goal_position": 0,
       "torque_enable": true},
      {"timestamp": 0.005, "position": 0, "speed": 0, "load": 0, "input_volts": 7, "temp": 30, "goal_position": 0,
       "torque_enable": true}]})";
  EXPECT_FALSE(FirmwareGain(ParseMeasuredRun(log, "bam.json", nullptr)).has_value());
}

TEST(BamLogTest, AFieldOfTheWrongTypeIsOneLineNamingTheFileAndTheEntry) {
  const std::string log = R"({"kp": 32, "entries": [
      {"timestamp": 0, "position": 0, "speed": 0, "load": 0, "input_volts": 7, "temp": 30, "goal_position": 0,
       "torque_enable": true},
      {"timestamp": 0.01, "position": "12", "speed": 0, "load": 0, "input_volts": 7, "temp": 30,
       "goal_position": 0, "torque_enable": true}]})";
  const std::string message = InputErrorOf([&] { ParseMeasuredRun(log, "bam.json", nullptr); });
  EXPECT_THAT(message, HasSubstr("bam.json"));
  EXPECT_THAT(message, HasSubstr("entries[1].position"));
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_THAT(InputErrorOf([] { ParseMeasuredRun(R"({"kp": 32, "entries": []})", "e.json", nullptr); }),
              HasSubstr("entries"));
  EXPECT_THAT(InputErrorOf([] { ParseMeasuredRun(R"({"kp": 32})", "k.json", nullptr); }), HasSubstr("entries"));
  EXPECT_THAT(InputErrorOf([] { ParseMeasuredRun("{\"entries\": [", "cut.json", nullptr); }), HasSubstr("cut.json"));
}

TEST(BamLogTest, OnlyAJsonObjectIsTakenForABamLog) {
  EXPECT_TRUE(IsBamLog("  \n{\"entries\": []}"));
  EXPECT_FALSE(IsBamLog("# orcs-sim log\n"));
  EXPECT_FALSE(IsBamLog("time_s,goal_deg\n"));
  EXPECT_FALSE(IsBamLog(""));
}

}  // namespace
}  // namespace orcs::identify
