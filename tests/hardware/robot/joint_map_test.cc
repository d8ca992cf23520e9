// The joint map (hardware/robot/joint_map.h): the two shipped maps, tick conversion and every bad-input check.
#include "hardware/robot/joint_map.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "model/core/error.h"

namespace orcs::hardware {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

/// The message of the InputError `f` throws ("" when it throws none).
std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

struct ExpectedJoint {
  const char* name;
  double min_deg;
  double max_deg;
};

// docs/spec/aseries.md, 4c: the 21 motors in order with their stops.
const std::vector<ExpectedJoint> kASeriesJoints{
    {"Waist", 0, 150},
    {"Right/ShoulderYaw", -150, 150},
    {"Left/ShoulderYaw", -150, 150},
    {"Right/ShoulderPitch", -106.5, 94.5},
    {"Left/ShoulderPitch", -94.5, 106.5},
    {"Right/Elbow", -106.5, 87},
    {"Left/Elbow", -87, 106.5},
    {"Right/HipRoll", -45, 150},
    {"Left/HipRoll", -150, 45},
    {"Right/HipPitch", -75, 40},
    {"Left/HipPitch", -40, 75},
    {"Right/HipYaw", -15, 150},
    {"Left/HipYaw", -150, 15},
    {"Right/Knee", 0, 150},
    {"Left/Knee", -150, 0},
    {"Right/AnkleYaw", -81, 29.5},
    {"Left/AnkleYaw", -29.5, 81},
    {"Right/AnklePitch", -66.5, 55},
    {"Left/AnklePitch", -55, 66.5},
    {"Head/Pan", -135, 135},
    {"Head/Tilt", -95, 150},
};

TEST(JointMapTest, ReadsTheASeriesMapInTheSpecsMotorOrder) {
  const JointMap map = ReadJointMap(ORCS_SOURCE_DIR "/scenarios/robots/aseries.joints.json");
  EXPECT_EQ(map.agent, "Humanoid");
  EXPECT_EQ(map.servo.name, "AX-12+");
  EXPECT_EQ(map.baud, 1000000);
  ASSERT_EQ(map.joints.size(), kASeriesJoints.size());
  for (std::size_t i = 0; i < kASeriesJoints.size(); ++i) {
    const JointMapping& m = map.joints[i];
    SCOPED_TRACE(m.joint);
    EXPECT_EQ(m.joint, kASeriesJoints[i].name);
    EXPECT_EQ(m.id, i + 1);
    EXPECT_EQ(m.direction, 1);
    EXPECT_EQ(m.zero_offset_deg, 0.0);
    EXPECT_DOUBLE_EQ(m.ticks_per_degree, 1024.0 / 300.0);
    EXPECT_EQ(m.center_tick, 512);
    EXPECT_EQ(m.min_deg, kASeriesJoints[i].min_deg);
    EXPECT_EQ(m.max_deg, kASeriesJoints[i].max_deg);
    EXPECT_EQ(m.max_torque, 1.0);
  }
  ASSERT_NE(map.Find("Right/Knee"), nullptr);
  EXPECT_EQ(map.Find("Right/Knee")->id, 14);
  EXPECT_EQ(map.Find("Knee"), nullptr);
}

TEST(JointMapTest, ReadsThePendulumMap) {
  const JointMap map = ReadJointMap(ORCS_SOURCE_DIR "/scenarios/robots/pendulum_xl330.joints.json");
  EXPECT_EQ(map.agent, "Pendulum");
  EXPECT_EQ(map.servo.name, "XL330-M288");
  EXPECT_EQ(map.baud, 1000000);
  ASSERT_EQ(map.joints.size(), 1u);
  const JointMapping& m = map.joints[0];
  EXPECT_EQ(m.joint, "Motor");
  EXPECT_EQ(m.id, 1);
  EXPECT_DOUBLE_EQ(m.ticks_per_degree, 4096.0 / 360.0);
  EXPECT_EQ(m.center_tick, 2048);
  EXPECT_EQ(m.min_deg, -150.0);
  EXPECT_EQ(m.max_deg, 150.0);
  EXPECT_EQ(ToTicks(m, 90.0), 2048 + 1024);
}

JointMapping Ax12(int direction, double offset = 0.0) {
  JointMapping m;
  m.joint = "J";
  m.direction = direction;
  m.zero_offset_deg = offset;
  m.ticks_per_degree = 1024.0 / 300.0;
  m.center_tick = 512;
  m.min_deg = -100.0;
  m.max_deg = 120.0;
  return m;
}

TEST(JointMapTest, ConvertsAnglesToTicksAndBack) {
  const JointMapping up = Ax12(1);
  EXPECT_EQ(ToTicks(up, 0.0), 512);
  EXPECT_EQ(ToTicks(up, 30.0), 512 + 102);  // 30° · 1024/300 = 102.4
  EXPECT_EQ(ToTicks(up, -150.0), 0);
  EXPECT_EQ(ToTicks(up, 150.0), 1024);  // the rated edge, one past max_tick: not clamped
  const JointMapping down = Ax12(-1);
  EXPECT_EQ(ToTicks(down, 30.0), 512 - 102);
  EXPECT_EQ(ToTicks(down, -30.0), 614);
  const JointMapping offset = Ax12(-1, 15.0);  // joint 0° is 15 servo degrees past the centre
  EXPECT_EQ(ToTicks(offset, 0.0), 512 + 51);  // 15 · 1024/300 = 51.2
  EXPECT_EQ(ToTicks(offset, 15.0), 512);
  for (const JointMapping& m : {up, down, offset}) {
    for (const double deg : {-97.3, -30.0, 0.0, 12.5, 88.8}) {
      EXPECT_NEAR(ToDegrees(m, ToTicks(m, deg)), deg, 0.5 / m.ticks_per_degree);  // within half a tick
    }
    for (const std::int64_t tick : {std::int64_t{0}, std::int64_t{100}, std::int64_t{512}, std::int64_t{1023}}) {
      EXPECT_EQ(ToTicks(m, ToDegrees(m, tick)), tick);
    }
  }
  EXPECT_DOUBLE_EQ(ToDegrees(up, 614), 102.0 * 300.0 / 1024.0);
  EXPECT_DOUBLE_EQ(ToDegrees(down, 614), -102.0 * 300.0 / 1024.0);
}

TEST(JointMapTest, ClampsToTheLimits) {
  const JointMapping m = Ax12(1);
  EXPECT_EQ(ClampToLimits(m, -150.0), -100.0);
  EXPECT_EQ(ClampToLimits(m, 130.0), 120.0);
  EXPECT_EQ(ClampToLimits(m, 7.5), 7.5);
  EXPECT_EQ(ClampToLimits(m, -100.0), -100.0);
}

TEST(JointMapTest, AJointsOwnResolutionAndCentreOverrideTheServos) {
  const JointMap map = ParseJointMap(nlohmann::json::parse(R"({"agent": "A", "servo": "XL330", "baud": 57600,
      "joints": [{"joint": "J", "id": 3, "min_deg": -10, "max_deg": 10, "ticks_per_degree": 10, "center_tick": 1000}]})"),
                                     "m.json");
  EXPECT_EQ(map.servo.name, "XL330-M288");
  EXPECT_EQ(map.baud, 57600);
  EXPECT_EQ(map.joints[0].ticks_per_degree, 10.0);
  EXPECT_EQ(map.joints[0].center_tick, 1000);
  EXPECT_EQ(map.joints[0].direction, 1);
  EXPECT_EQ(map.joints[0].max_torque, 1.0);
  EXPECT_EQ(ToTicks(map.joints[0], 5.0), 1050);
  EXPECT_EQ(ParseJointMap(nlohmann::json::parse(R"({"agent": "A", "servo": "AX-12", "baud": 1,
      "joints": [{"joint": "J", "id": 0, "min_deg": -1, "max_deg": 1}]})"),
                          "m.json")
                .servo.name,
            "AX-12+");
}

/// A valid one-joint map with `edit` applied; the message of parsing it.
std::string ErrorOf(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = nlohmann::json::parse(R"({"agent": "Humanoid", "servo": "AX-12+", "baud": 1000000,
      "joints": [{"joint": "Waist", "id": 1, "direction": 1, "zero_offset_deg": 0, "min_deg": 0, "max_deg": 150,
                  "max_torque": 1.0},
                 {"joint": "Right/Knee", "id": 14, "direction": -1, "zero_offset_deg": 0, "min_deg": 0,
                  "max_deg": 150, "max_torque": 0.5}]})");
  edit(j);
  return InputErrorOf([&] { ParseJointMap(j, "aseries.json"); });
}

TEST(JointMapTest, TheTestMapItselfIsValid) { EXPECT_EQ(ErrorOf([](nlohmann::json&) {}), ""); }

struct BadCase {
  const char* what;
  std::function<void(nlohmann::json&)> edit;
  const char* field;
  const char* expected;
};

TEST(JointMapTest, EachBadInputIsOneLineNamingTheFileAndTheField) {
  const std::vector<BadCase> cases{
      {"unknown top-level key", [](nlohmann::json& j) { j["bauds"] = 1; }, "field 'bauds'", "no such field"},
      {"unknown joint key", [](nlohmann::json& j) { j["joints"][1]["offset"] = 1; }, "field 'joints[1].offset'",
       "no such field"},
      {"unknown servo", [](nlohmann::json& j) { j["servo"] = "MX-28"; }, "field 'servo'", "'XL330-M288'"},
      {"id above 252", [](nlohmann::json& j) { j["joints"][1]["id"] = 253; }, "field 'joints[1].id'", "0…252"},
      {"negative id", [](nlohmann::json& j) { j["joints"][0]["id"] = -1; }, "field 'joints[0].id'", "0…252"},
      {"id used twice", [](nlohmann::json& j) { j["joints"][1]["id"] = 1; }, "field 'joints[1].id'",
       "the id of joints[0]"},
      {"joint named twice", [](nlohmann::json& j) { j["joints"][1]["joint"] = "Waist"; }, "field 'joints[1].joint'",
       "mapped by joints[0]"},
      {"direction 0", [](nlohmann::json& j) { j["joints"][1]["direction"] = 0; }, "field 'joints[1].direction'",
       "1 or -1"},
      {"direction 2", [](nlohmann::json& j) { j["joints"][0]["direction"] = 2; }, "field 'joints[0].direction'",
       "1 or -1"},
      {"min equals max", [](nlohmann::json& j) { j["joints"][0]["max_deg"] = 0; }, "field 'joints[0].max_deg'",
       "above min_deg"},
      {"min above max", [](nlohmann::json& j) { j["joints"][1]["min_deg"] = 160; }, "field 'joints[1].max_deg'",
       "above min_deg"},
      {"max_torque 0", [](nlohmann::json& j) { j["joints"][0]["max_torque"] = 0; }, "field 'joints[0].max_torque'",
       "(0, 1]"},
      {"max_torque above 1", [](nlohmann::json& j) { j["joints"][1]["max_torque"] = 1.5; },
       "field 'joints[1].max_torque'", "(0, 1]"},
      {"max beyond the servo", [](nlohmann::json& j) { j["joints"][0]["max_deg"] = 151; }, "field 'joints[0].max_deg'",
       "ticks 0…1023"},
      {"min beyond the servo (direction -1)", [](nlohmann::json& j) { j["joints"][1]["min_deg"] = -151; },
       "field 'joints[1].min_deg'", "ticks 0…1023"},
      {"offset pushes a limit out", [](nlohmann::json& j) { j["joints"][0]["zero_offset_deg"] = 10; },
       "field 'joints[0].max_deg'", "ticks 0…1023"},
      {"baud 0", [](nlohmann::json& j) { j["baud"] = 0; }, "field 'baud'", "positive baud"},
      {"negative baud", [](nlohmann::json& j) { j["baud"] = -9600; }, "field 'baud'", "positive baud"},
      {"no joints", [](nlohmann::json& j) { j["joints"] = nlohmann::json::array(); }, "field 'joints'",
       "at least one joint"},
      {"missing id", [](nlohmann::json& j) { j["joints"][0].erase("id"); }, "field 'joints[0].id'", "missing"},
      {"missing agent", [](nlohmann::json& j) { j.erase("agent"); }, "field 'agent'", "missing"},
      {"id not a number", [](nlohmann::json& j) { j["joints"][0]["id"] = "1"; }, "field 'joints[0].id'", "0…252"},
      {"bad ticks_per_degree", [](nlohmann::json& j) { j["joints"][0]["ticks_per_degree"] = 0; },
       "field 'joints[0].ticks_per_degree'", "positive"},
      {"centre tick beyond the servo", [](nlohmann::json& j) { j["joints"][0]["center_tick"] = 1024; },
       "field 'joints[0].center_tick'", "0…1023"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string message = ErrorOf(c.edit);
    EXPECT_THAT(message, HasSubstr("aseries.json: "));
    EXPECT_THAT(message, HasSubstr(c.field));
    EXPECT_THAT(message, HasSubstr(c.expected));
    EXPECT_THAT(message, Not(HasSubstr("\n")));
  }
}

TEST(JointMapTest, ReadingNamesTheFile) {
  EXPECT_THAT(InputErrorOf([] { ReadJointMap("/nonexistent/robot.joints.json"); }),
              HasSubstr("/nonexistent/robot.joints.json"));
  EXPECT_THAT(InputErrorOf([] { ParseJointMap(nlohmann::json::array(), "m.json"); }),
              HasSubstr("m.json: expected a joint map"));
}

}  // namespace
}  // namespace orcs::hardware
