#include "model/identify/measured_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "model/core/text.h"
#include "model/core/text_file.h"
#include "model/identify/replay.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::identify {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

// The head of a real log: orcs-sim -env scenarios/environments/pendulum.xml -play Pendulum
// scenarios/motions/pendulum_steps.csv --duration 5 --log '.*Motor/(JointAngle|DesiredAngle|DesiredTorque)'.
constexpr const char* kPendulumLog =
    "# orcs-sim log\n"
    "# environment: scenarios/environments/pendulum.xml\n"
    "# seed: 0\n"
    "# columns: time,/Sim/Pendulum/Motor/DesiredAngle,/Sim/Pendulum/Motor/DesiredTorque,"
    "/Sim/Pendulum/Motor/JointAngle\n"
    "0,0,0.586810005,0\n"
    "0.01,0,1,-0.0501782495117635\n"
    "0.02,0,1,0.19046842437259234\n"
    "0.03,0,1,-0.2494817702416845\n";

// An A-Series style log: motor names with a slash, columns the gap does not need (an accelerometer, a
// MotorTorque), a motor that is measured but not commanded.
constexpr const char* kHumanoidLog =
    "# columns: time,/Sim/Humanoid/Right/Knee/JointAngle,/Sim/Humanoid/Accel/Acceleration.x,"
    "/Sim/Humanoid/Left/Knee/DesiredTorque,/Sim/Humanoid/Right/Knee/DesiredAngle,"
    "/Sim/Humanoid/Left/Knee/DesiredAngle,/Sim/Humanoid/Right/Knee/MotorTorque,"
    "/Sim/Humanoid/Right/Knee/DesiredTorque,/Sim/Humanoid/Head/Pan/JointAngle\n"
    "0,10,0.1,0.5,20,-20,0.01,1,0\n"
    "0.02,11,0.2,0.6,21,-21,0.02,0.9,1\n";

// The head of a real A-Series log, verbatim: orcs-sim -env scenarios/environments/leg_swing.xml -play Humanoid
// scenarios/motions/leg_swing.csv --duration 1 --log '.*Knee/(JointAngle|DesiredAngle|DesiredTorque|MotorTorque)'
// --log '.*Accel.*'. Columns outside /Sim/ and the accelerometers are not motor columns.
constexpr const char* kLegSwingLog =
    "# orcs-sim log\n"
    "# environment: scenarios/environments/leg_swing.xml\n"
    "# seed: 0\n"
    "# duration: 1 s\n"
    "# columns: time,/AccelSensor/Deviation,/AccelSensor/LowPassFilterDelay,/Sim/Humanoid/Right/Knee/DesiredAngle,"
    "/Sim/Humanoid/Right/Knee/DesiredTorque,/Sim/Humanoid/Right/Knee/JointAngle,/Sim/Humanoid/Left/Knee/DesiredAngle,"
    "/Sim/Humanoid/Left/Knee/DesiredTorque,/Sim/Humanoid/Left/Knee/JointAngle,/Sim/Humanoid/ABFR/AccelAxis1,"
    "/Sim/Humanoid/ABFR/AccelAxis2,/Sim/Humanoid/ABHR/AccelAxis1,/Sim/Humanoid/ABHR/AccelAxis2,"
    "/Sim/Humanoid/ABSR/AccelAxis1,/Sim/Humanoid/ABSR/AccelAxis2,/Sim/Humanoid/ABAR/AccelAxis1,"
    "/Sim/Humanoid/ABAR/AccelAxis2,/Sim/Humanoid/ABFL/AccelAxis1,/Sim/Humanoid/ABFL/AccelAxis2,"
    "/Sim/Humanoid/ABHL/AccelAxis1,/Sim/Humanoid/ABHL/AccelAxis2,/Sim/Humanoid/ABML/AccelAxis1,"
    "/Sim/Humanoid/ABML/AccelAxis2,/Sim/Humanoid/ABAL/AccelAxis1,/Sim/Humanoid/ABAL/AccelAxis2\n"
    "0,1e-04,1,0,0.586810005,0,0,0.586810005,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n"
    "0.01,1e-04,1,0,0.586810005,-0.04234062062728432,0,0.586810005,-0.11111562949530618,5.38851931019267e-05,"
    "0.00015823772363317826,-0.0001361116077602894,-9.758184564936364,0.00012807564569128997,-0.000294467916690887,"
    "-9.782136121053881,-0.00012173540305691755,-0.0001826177995112266,-0.00027811498081127995,"
    "-0.00020262091516643618,9.758222297313974,-5.214766564992624e-05,4.3559242703838026e-05,-9.782175976994342,"
    "0.00011131378459733817\n"
    "0.02,1e-04,1,0,0.586810005,0.10842987221484288,0,0.586810005,0.38332307892833933,1.219058910918743e-05,"
    "-0.00023561656153985044,-9.466534622620511e-05,-9.820106662529899,0.00013383280335860104,"
    "4.8728143655821334e-05,-9.815495861593057,-0.00015246263828017727,-4.48116332095356e-05,"
    "-7.121276487632476e-05,-0.00016052736559768363,9.820023924608963,0.00022877648114658913,"
    "1.3837235577777942e-05,-9.815409456801278,9.193822113407012e-05\n";

// A run written by hand: `rows` as given after a native header of one pendulum motor.
std::string PendulumLog(const std::string& rows) {
  return "# columns: time,/Sim/Pendulum/Motor/DesiredAngle,/Sim/Pendulum/Motor/DesiredTorque,"
         "/Sim/Pendulum/Motor/JointAngle\n" +
         rows;
}

TEST(MeasuredRunTest, ParsesNativePendulumLog) {
  const MeasuredRun run = ParseMeasuredRun(kPendulumLog, "p.csv");
  EXPECT_EQ(run.source, "p.csv");
  EXPECT_EQ(run.agent, "Pendulum");
  EXPECT_THAT(run.motors, ElementsAre("Motor"));
  EXPECT_THAT(run.commanded, ElementsAre("Motor"));
  EXPECT_THAT(run.time, ElementsAre(0.0, 0.01, 0.02, 0.03));
  EXPECT_DOUBLE_EQ(run.step, 0.01);
  EXPECT_THAT(run.desired_angle.at("Motor"), ElementsAre(0.0, 0.0, 0.0, 0.0));
  EXPECT_THAT(run.desired_torque.at("Motor"), ElementsAre(0.586810005, 1.0, 1.0, 1.0));
  EXPECT_THAT(run.joint_angle.at("Motor"),
              ElementsAre(0.0, -0.0501782495117635, 0.19046842437259234, -0.2494817702416845));
  EXPECT_THAT(run.lines, ElementsAre(5, 6, 7, 8));
}

TEST(MeasuredRunTest, ParsesARealASeriesLog) {
  const MeasuredRun run = ParseMeasuredRun(kLegSwingLog, "leg_swing.csv");
  EXPECT_EQ(run.agent, "Humanoid");
  EXPECT_THAT(run.motors, ElementsAre("Right/Knee", "Left/Knee"));
  EXPECT_THAT(run.commanded, ElementsAre("Right/Knee", "Left/Knee"));
  EXPECT_EQ(run.joint_angle.size(), 2u);
  EXPECT_DOUBLE_EQ(run.step, 0.01);
  EXPECT_THAT(run.joint_angle.at("Left/Knee"), ElementsAre(0.0, -0.11111562949530618, 0.38332307892833933));
  EXPECT_THAT(run.desired_torque.at("Right/Knee"), ElementsAre(0.586810005, 0.586810005, 0.586810005));
  EXPECT_THAT(run.lines, ElementsAre(6, 7, 8));
}

// The accelerometer axes of an orcs log are read beside the motors, in column order, in m/s² (issue 49: they enter
// the comparison); the /AccelSensor/... values are no readings and stay out.
TEST(MeasuredRunTest, ReadsTheAccelerometerAxesOfAnOrcsLog) {
  const MeasuredRun run = ParseMeasuredRun(kLegSwingLog, "leg_swing.csv");
  ASSERT_EQ(run.accelerometers.size(), 16u);
  EXPECT_EQ(run.accelerometers.front(), "ABFR/AccelAxis1");
  EXPECT_EQ(run.accelerometers[3], "ABHR/AccelAxis2");
  EXPECT_EQ(run.accelerometers.back(), "ABAL/AccelAxis2");
  EXPECT_THAT(run.acceleration.at("ABHR/AccelAxis2"), ElementsAre(0.0, -9.758184564936364, -9.820106662529899));
  EXPECT_THAT(run.acceleration_noise, IsEmpty());  // an orcs log's noise is the model's
  EXPECT_EQ(AccelerometerColumn("Humanoid", "ABSR/AccelAxis1"), "/Sim/Humanoid/ABSR/AccelAxis1");
  // A column that only looks like one (no board, another quantity) is not an axis.
  const MeasuredRun humanoid = ParseMeasuredRun(kHumanoidLog, "h.csv");
  EXPECT_THAT(humanoid.accelerometers, IsEmpty());
}

TEST(MeasuredRunTest, ParsesASeriesMotorNamesWithSlashAndIgnoresOtherColumns) {
  const MeasuredRun run = ParseMeasuredRun(kHumanoidLog, "h.csv");
  EXPECT_EQ(run.agent, "Humanoid");
  EXPECT_THAT(run.motors, ElementsAre("Right/Knee", "Head/Pan"));  // JointAngle columns, in column order
  EXPECT_THAT(run.commanded, ElementsAre("Left/Knee", "Right/Knee"));  // order of their first input column
  EXPECT_DOUBLE_EQ(run.step, 0.02);
  EXPECT_THAT(run.joint_angle.at("Right/Knee"), ElementsAre(10.0, 11.0));
  EXPECT_THAT(run.joint_angle.at("Head/Pan"), ElementsAre(0.0, 1.0));
  EXPECT_THAT(run.desired_angle.at("Right/Knee"), ElementsAre(20.0, 21.0));
  EXPECT_THAT(run.desired_torque.at("Right/Knee"), ElementsAre(1.0, 0.9));
  EXPECT_THAT(run.desired_angle.at("Left/Knee"), ElementsAre(-20.0, -21.0));
  EXPECT_THAT(run.desired_torque.at("Left/Knee"), ElementsAre(0.5, 0.6));
  EXPECT_EQ(run.desired_angle.count("Head/Pan"), 0u);
  EXPECT_EQ(run.joint_angle.count("Accel"), 0u);
  EXPECT_EQ(run.joint_angle.size(), 2u);
}

TEST(MeasuredRunTest, AcceptsCrLfBlankLinesQuotedFieldsAndCommentsAnywhere) {
  const std::string text =
      "# columns: time,/Sim/P/M/JointAngle,/Sim/P/Note\r\n"
      "\r\n"
      "0, 1 ,\"a, b\"\r\n"
      "# a comment between rows\r\n"
      "0.5,2,\"say \"\"hi\"\"\"\r\n";
  const MeasuredRun run = ParseMeasuredRun(text, "c.csv");
  EXPECT_THAT(run.joint_angle.at("M"), ElementsAre(1.0, 2.0));
  EXPECT_THAT(run.commanded, IsEmpty());
  EXPECT_THAT(run.lines, ElementsAre(3, 5));
  EXPECT_DOUBLE_EQ(run.step, 0.5);
}

TEST(MeasuredRunTest, ReadsAFileAndNamesAnUnreadableOne) {
  const TempDir dir;
  const std::string path = dir.Write("p.csv", kPendulumLog);
  EXPECT_EQ(ReadMeasuredRun(path).source, path);
  EXPECT_EQ(ReadMeasuredRun(path).joint_angle.at("Motor").at(3), -0.2494817702416845);
  const std::string missing = dir.PathOf("missing.csv");
  EXPECT_EQ(InputErrorOf([&] { ReadMeasuredRun(missing); }), missing + ": cannot read the file: no such file");
}

TEST(MeasuredRunTest, RejectsEmptyAndRowlessAndOneRowFiles) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun("", "run.csv"); }), "run.csv: no data rows");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("\n# nothing\n"), "run.csv"); }),
            "run.csv: no data rows");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n"), "run.csv"); }),
            "run.csv: expected at least 2 data rows (a time step needs two times), found 1");
}

TEST(MeasuredRunTest, RequiresTheColumnsCommentBeforeTheRows) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun("# log\n0,1\n0.01,2\n", "run.csv"); }),
            "run.csv: no '# columns:' comment naming the columns (orcs-sim logs have one; other CSVs need a "
            "column mapping)");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun("0,1\n# columns: time,/Sim/P/M/JointAngle\n0.01,2\n", "run.csv"); }),
            "run.csv:2: '# columns:' comes after the first data row (line 1); it must name the columns before them");
  EXPECT_EQ(InputErrorOf([] {
              ParseMeasuredRun("# columns: time,/Sim/P/M/JointAngle\n# columns: time\n0,1\n0.01,2\n", "run.csv");
            }),
            "run.csv:2: a second '# columns:' comment (the first is on line 1)");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun("# columns: t,/Sim/P/M/JointAngle\n0,1\n0.01,2\n", "run.csv"); }),
            "run.csv: expected the first column to be 'time', found 't'");
}

TEST(MeasuredRunTest, RejectsARowWithTheWrongNumberOfFields) {
  const std::string text = PendulumLog("0,0,1,0\n0.01,0,1,0\n0.02,0,1\n");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(text, "run.csv"); }), "run.csv:4: expected 4 fields, found 3");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0,7\n"), "run.csv"); }),
            "run.csv:3: expected 4 fields, found 5");
}

TEST(MeasuredRunTest, RejectsCellsThatAreNotFiniteNumbersNamingLineAndColumn) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,nan\n"), "run.csv"); }),
            "run.csv:3: column '/Sim/Pendulum/Motor/JointAngle': 'nan' is not a finite number");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,inf,1,0\n"), "run.csv"); }),
            "run.csv:3: column '/Sim/Pendulum/Motor/DesiredAngle': 'inf' is not a finite number");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,,0\n0.01,0,1,0\n"), "run.csv"); }),
            "run.csv:2: column '/Sim/Pendulum/Motor/DesiredTorque': '' is not a finite number");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\nabc,0,1,0\n"), "run.csv"); }),
            "run.csv:3: column 'time': 'abc' is not a finite number");
  // Columns the gap does not need may hold anything.
  EXPECT_NO_THROW(ParseMeasuredRun("# columns: time,/Sim/P/M/JointAngle,/Sim/P/Name\n0,1,x\n0.1,2,\n", "ok.csv"));
}

TEST(MeasuredRunTest, TimeMustStartAtZero) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0.01,0,1,0\n0.02,0,1,0\n"), "run.csv"); }),
            "run.csv:2: column 'time': expected the first time to be 0 s, found 0.01 s");
  EXPECT_EQ(ParseMeasuredRun(PendulumLog("1e-10,0,1,0\n0.01,0,1,0\n"), "run.csv").time.front(), 1e-10);
}

TEST(MeasuredRunTest, TimeMustIncreaseStrictly) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0\n0.01,0,1,0\n"), "run.csv"); }),
            "run.csv:4: column 'time': expected a time after 0.01 s (line 3), found 0.01 s");
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0\n\n0.005,0,1,0\n"), "r.csv"); }),
            "r.csv:5: column 'time': expected a time after 0.01 s (line 3), found 0.005 s");
}

TEST(MeasuredRunTest, TimeStepMustBeUniformWithinOneMillionth) {
  EXPECT_EQ(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0\n0.03,0,1,0\n"), "run.csv"); }),
            "run.csv:4: column 'time': expected a uniform step of 0.01 s (that of the first two rows), found "
            "0.02 s from 0.01 s to 0.03 s");
  // 1e-6 of the step is the limit: 0.5e-8 s off passes, 2e-8 s off does not.
  EXPECT_NO_THROW(ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0\n0.020000005,0,1,0\n"), "run.csv"));
  EXPECT_THAT(InputErrorOf([] { ParseMeasuredRun(PendulumLog("0,0,1,0\n0.01,0,1,0\n0.02000002,0,1,0\n"), "r.csv"); }),
              HasSubstr("r.csv:4: column 'time': expected a uniform step of 0.01 s"));
}

TEST(MeasuredRunTest, StepIsTheMeanStepOfTheWholeRun) {
  // Times printed with rounding: the mean over the run is the rig's step.
  const MeasuredRun run = ParseMeasuredRun(PendulumLog("0,0,1,0\n0.0100000001,0,1,0\n0.02,0,1,0\n"), "run.csv");
  EXPECT_DOUBLE_EQ(run.step, 0.01);
}

TEST(MeasuredRunTest, RejectsColumnsOfTwoAgents) {
  const std::string text =
      "# columns: time,/Sim/Humanoid/Right/Knee/JointAngle,/Sim/Pendulum/Motor/JointAngle\n0,1,2\n0.01,1,2\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(text, "run.csv"); }),
            "run.csv: columns of two agents, 'Humanoid' and 'Pendulum'");
}

TEST(MeasuredRunTest, RejectsALogWithoutJointAngleColumn) {
  const std::string text =
      "# columns: time,/Sim/Pendulum/Motor/DesiredAngle,/Sim/Pendulum/Motor/DesiredTorque,"
      "/Sim/Pendulum/Motor/MotorTorque\n0,1,2,3\n0.01,1,2,3\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(text, "run.csv"); }),
            "run.csv: no '/Sim/<agent>/<motor>/JointAngle' column");
}

TEST(MeasuredRunTest, MissingColumnNamesFileAndColumn) {
  const std::string angle_only =
      "# columns: time,/Sim/Humanoid/Right/Knee/DesiredAngle,/Sim/Humanoid/Right/Knee/JointAngle\n0,1,2\n0.01,1,2\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(angle_only, "run.csv"); }),
            "run.csv: no column '/Sim/Humanoid/Right/Knee/DesiredTorque' to go with "
            "'/Sim/Humanoid/Right/Knee/DesiredAngle' (a commanded motor needs both)");
  const std::string torque_only =
      "# columns: time,/Sim/Humanoid/Right/Knee/JointAngle,/Sim/Humanoid/Right/Knee/DesiredTorque\n0,1,2\n0.01,1,2\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(torque_only, "run.csv"); }),
            "run.csv: no column '/Sim/Humanoid/Right/Knee/DesiredAngle' to go with "
            "'/Sim/Humanoid/Right/Knee/DesiredTorque' (a commanded motor needs both)");
}

TEST(MeasuredRunTest, RejectsAMotorColumnTwice) {
  const std::string text = "# columns: time,/Sim/P/M/JointAngle,x,/Sim/P/M/JointAngle\n0,1,2,3\n0.01,1,2,3\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(text, "run.csv"); }),
            "run.csv: column '/Sim/P/M/JointAngle' appears twice (fields 2 and 4)");
}

TEST(MeasuredRunTest, RejectsAnUnterminatedQuote) {
  const std::string text = "# columns: time,/Sim/P/M/JointAngle,n\n0,1,\"ab\n0.1,1,x\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(text, "q.csv"); }),
            "q.csv:2: field '\"ab' has no closing quote");
}

// ---------------------------------------------------------------------------------------------------------
// Column mappings

// A logger's CSV: ';'-separated, time in ms, angles in encoder ticks (0.29296875°/tick, 512 = 0°), torque not
// logged (always full).
constexpr const char* kLoggerCsv =
    "# exported by the robot's logger\n"
    "\"t_ms\"; cmd_knee ; pos_knee;pos_hip\n"
    "0;10;512;60\n"
    "20;20;522;61\n"
    "40;30;532;62\n";

constexpr const char* kLoggerMapping = R"({
  "comment": "the robot's logger",
  "agent": "Humanoid",
  "delimiter": ";",
  "time": {"column": "t_ms", "scale": 0.001},
  "channels": [
    {"motor": "Right/Knee",
     "desired_angle": {"column": "cmd_knee"},
     "desired_torque": {"constant": 1},
     "joint_angle": {"column": "pos_knee", "scale": 0.29296875, "offset": -150}},
    {"motor": "Right/Hip", "joint_angle": {"column": "pos_hip"}}
  ]
})";

ColumnMapping Mapping(const std::string& json) { return ParseColumnMapping(nlohmann::json::parse(json), "m.json"); }

TEST(MeasuredRunTest, ParsesAColumnMapping) {
  const ColumnMapping m = Mapping(kLoggerMapping);
  EXPECT_EQ(m.source, "m.json");
  EXPECT_EQ(m.agent, "Humanoid");
  EXPECT_EQ(m.delimiter, ';');
  EXPECT_EQ(m.time.column, "t_ms");
  EXPECT_EQ(m.time.scale, 0.001);
  ASSERT_EQ(m.channels.size(), 2u);
  EXPECT_EQ(m.channels[0].motor, "Right/Knee");
  ASSERT_TRUE(m.channels[0].desired_torque && m.channels[0].desired_torque->constant);
  EXPECT_EQ(*m.channels[0].desired_torque->constant, 1.0);
  EXPECT_EQ(m.channels[0].joint_angle->offset, -150.0);
  EXPECT_FALSE(m.channels[1].desired_angle.has_value());
  EXPECT_FALSE(m.channels[1].desired_torque.has_value());
  EXPECT_EQ(Mapping(R"({"agent": "P", "time": {"column": "t"}, "channels": [{"motor": "M",
                        "joint_angle": {"column": "a"}}]})").delimiter, ',');
}

TEST(MeasuredRunTest, MappedCsvWithMillisecondsScaleOffsetAndConstantTorque) {
  const ColumnMapping m = Mapping(kLoggerMapping);
  const MeasuredRun run = ParseMeasuredRun(kLoggerCsv, "log.csv", &m);
  EXPECT_EQ(run.agent, "Humanoid");
  EXPECT_THAT(run.motors, ElementsAre("Right/Knee", "Right/Hip"));
  EXPECT_THAT(run.commanded, ElementsAre("Right/Knee"));
  EXPECT_THAT(run.time, ElementsAre(0.0, 0.02, 0.04));
  EXPECT_DOUBLE_EQ(run.step, 0.02);
  EXPECT_THAT(run.desired_angle.at("Right/Knee"), ElementsAre(10.0, 20.0, 30.0));
  EXPECT_THAT(run.desired_torque.at("Right/Knee"), ElementsAre(1.0, 1.0, 1.0));
  EXPECT_THAT(run.joint_angle.at("Right/Knee"), ElementsAre(0.0, 10 * 0.29296875, 20 * 0.29296875));
  EXPECT_THAT(run.joint_angle.at("Right/Hip"), ElementsAre(60.0, 61.0, 62.0));
  EXPECT_THAT(run.lines, ElementsAre(3, 4, 5));
}

// Issue 18: a joint angle beyond ±360° is not a measurement (1e308° was fitted; so would be encoder ticks mapped
// without their scale). The error names the file, the line and the column.
TEST(MeasuredRunTest, AJointAngleBeyond360DegreesIsRefusedNamingFileLineAndColumn) {
  const ColumnMapping m = Mapping(kLoggerMapping);
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n0;10;512;60\n20;20;522;600\n", "l.csv", &m); }),
            "l.csv:3: column 'pos_hip': '600' gives 600°, not a physical joint angle (expected −360…360°)");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n0;400;512;60\n20;20;522;61\n", "l.csv", &m); }),
            "l.csv:2: column 'cmd_knee': '400' gives 400°, not a physical joint angle (expected −360…360°)");
  const std::string native = std::string("# columns: time,/Sim/P/M/JointAngle\n0,0\n0.01,1e308\n");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(native, "run.csv", nullptr); }),
            "run.csv:3: column '/Sim/P/M/JointAngle': '1e308' gives 1e+308°, not a physical joint angle (expected −360…360°)");
}

TEST(MeasuredRunTest, ReadsAMappingFileAndAMappedRunFile) {
  const TempDir dir;
  const ColumnMapping m = ReadColumnMapping(dir.Write("mapping.json", kLoggerMapping));
  EXPECT_EQ(m.source, dir.PathOf("mapping.json"));
  const MeasuredRun run = ReadMeasuredRun(dir.Write("log.csv", kLoggerCsv), &m);
  EXPECT_THAT(run.time, ElementsAre(0.0, 0.02, 0.04));
  EXPECT_EQ(InputErrorOf([&] { ReadColumnMapping(dir.Write("bad.json", "{\"agent\": \n")); }),
            dir.PathOf("bad.json") + ":2: malformed JSON: syntax error while parsing value - unexpected end of input; "
                                     "expected '[', '{', or a literal");
}

TEST(MeasuredRunTest, MappingErrorsNameTheField) {
  const std::string ok_channel = R"("channels": [{"motor": "M", "joint_angle": {"column": "a"}}])";
  const std::string ok_time = R"("time": {"column": "t"})";
  auto error = [](const std::string& json) { return InputErrorOf([&] { Mapping(json); }); };
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_time + ", " + ok_channel + R"(, "agnet": 1})"),
            "m.json: field 'agnet' expected no such field (allowed: agent, time, channels, delimiter, firmware_kp, "
            "winding_temperature, supply_voltage, command_timing, accelerometers), found 'agnet'");
  EXPECT_EQ(error("{" + ok_time + ", " + ok_channel + "}"),
            "m.json: field 'agent' expected a value, found nothing (the field is missing)");
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_channel + "}"),
            "m.json: field 'time' expected a value, found nothing (the field is missing)");
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_time + "}"),
            "m.json: field 'channels' expected a value, found nothing (the field is missing)");
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_time + R"(, "channels": [{"motor": "M", "joint_angle": {"column": 3}}]})"),
            "m.json: field 'channels[0].joint_angle.column' expected a column name, found the number 3");
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_time +
                  R"(, "channels": [{"motor": "M", "joint_angle": {"column": "a", "scal": 2}}]})"),
            "m.json: field 'channels[0].joint_angle.scal' expected no such field (allowed: column, scale, offset, "
            "constant, header), found 'scal'");
  EXPECT_EQ(error(R"({"agent": "P", )" + ok_time +
                  R"(, "channels": [{"motor": "M", "joint_angle": {"column": "a", "scale": "2"}}]})"),
            "m.json: field 'channels[0].joint_angle.scale' expected a finite number, found the string \"2\"");
  EXPECT_EQ(error(R"({"agent": "P", "time": {"column": "t"}, "channels": {}})"),
            "m.json: field 'channels' expected an array, found an object");
  EXPECT_EQ(error("[1]"), "m.json: expected a column mapping (a JSON object), found an array of 1");
}

// A mapped CSV's accelerometer axes: a column each, scaled to m/s², with the noise of the board that recorded them;
// a mistyped axis, an axis named twice, a noise that is no σ and a reading no accelerometer gives are one line each.
TEST(MeasuredRunTest, MappedAccelerometersReadTheirColumnsScaleAndNoise) {
  const std::string csv = "t,cmd,pos,ax_g,ay_g\n0,0,0,0,1\n0.01,1,0.5,0.1,0.9\n0.02,2,1,0.2,0.8\n";
  const std::string head = R"({"agent": "Humanoid", "time": {"column": "t"}, "channels": [{"motor": "Waist",
      "desired_angle": {"column": "cmd"}, "desired_torque": {"constant": 1}, "joint_angle": {"column": "pos"}}], )";
  const ColumnMapping mapping = Mapping(head + R"("accelerometers": [
      {"channel": "ABSR/AccelAxis1", "column": "ax_g", "scale": 9.81, "noise": 0.03},
      {"channel": "ABSR/AccelAxis2", "column": "ay_g", "scale": 9.81}]})");
  const MeasuredRun run = ParseMeasuredRun(csv, "run.csv", &mapping);
  EXPECT_THAT(run.accelerometers, ElementsAre("ABSR/AccelAxis1", "ABSR/AccelAxis2"));
  EXPECT_THAT(run.acceleration.at("ABSR/AccelAxis1"), ElementsAre(0.0, 0.1 * 9.81, 0.2 * 9.81));
  EXPECT_THAT(run.acceleration.at("ABSR/AccelAxis2"), ElementsAre(9.81, 0.9 * 9.81, 0.8 * 9.81));
  EXPECT_EQ(run.acceleration_noise.at("ABSR/AccelAxis1"), 0.03);
  EXPECT_EQ(run.acceleration_noise.count("ABSR/AccelAxis2"), 0u);

  auto error = [&](const std::string& axes) { return InputErrorOf([&] { Mapping(head + axes + "}"); }); };
  EXPECT_EQ(error(R"("accelerometers": [{"channel": "ABSR/AccelAxis3", "column": "ax_g"}])"),
            "m.json: field 'accelerometers[0].channel' expected a board's axis (e.g. \"ABSR/AccelAxis1\"), found "
            "'ABSR/AccelAxis3'");
  EXPECT_EQ(error(R"("accelerometers": [{"channel": "ABSR/AccelAxis1", "column": "ax_g"},
                                        {"channel": "ABSR/AccelAxis1", "column": "ay_g"}])"),
            "m.json: field 'accelerometers[1].channel' expected an axis not named before, found 'ABSR/AccelAxis1'");
  EXPECT_EQ(error(R"("accelerometers": [{"channel": "ABSR/AccelAxis1", "column": "ax_g", "noise": 0}])"),
            "m.json: field 'accelerometers[0].noise' expected a positive σ in m/s², found 0");
  EXPECT_EQ(error(R"("accelerometers": [{"channel": "ABSR/AccelAxis1"}])"),
            "m.json: field 'accelerometers[0]' expected an object with \"column\", found none");
  const ColumnMapping huge = Mapping(head + R"("accelerometers": [{"channel": "ABSR/AccelAxis1", "column": "ax_g",
      "scale": 1e4}]})");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(csv, "run.csv", &huge); }),
            "run.csv:4: column 'ax_g': '0.2' gives 2000 m/s², not an accelerometer's reading "
            "(expected −1000…1000 m/s²)");
}

TEST(MeasuredRunTest, MappingRulesBeyondTypes) {
  auto error = [](const std::string& channels, const std::string& extra = "") {
    return InputErrorOf(
        [&] { Mapping(R"({"agent": "P", "time": {"column": "t"}, "channels": [)" + channels + "]" + extra + "}"); });
  };
  EXPECT_EQ(error(R"({"motor": "M", "desired_angle": {"column": "c"}, "joint_angle": {"column": "a"}})"),
            "m.json: field 'channels[0].desired_torque' expected a value, since 'desired_angle' is given (a commanded "
            "motor needs both), found nothing (the field is missing)");
  EXPECT_EQ(error(R"({"motor": "M", "desired_torque": {"constant": 1}, "joint_angle": {"column": "a"}})"),
            "m.json: field 'channels[0].desired_angle' expected a value, since 'desired_torque' is given (a commanded "
            "motor needs both), found nothing (the field is missing)");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"constant": 1}})"),
            "m.json: field 'channels[0].joint_angle' expected a column, found a constant");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"column": "a", "constant": 1}})"),
            "m.json: field 'channels[0].joint_angle' expected either \"column\" or \"constant\", found both");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"scale": 2}})"),
            "m.json: field 'channels[0].joint_angle' expected an object with \"column\" or \"constant\", "
            "found neither");
  EXPECT_EQ(error(R"({"motor": "M", "desired_angle": {"constant": 1, "scale": 2}, "desired_torque": {"constant": 1},
                      "joint_angle": {"column": "a"}})"),
            "m.json: field 'channels[0].desired_angle.scale' expected nothing beside \"constant\", found the number 2");
  EXPECT_EQ(error(R"({"motor": "M", "desired_angle": {"column": "c"}, "desired_torque": {"constant": 1}})"),
            "m.json: field 'channels' expected at least one channel with a 'joint_angle', found none");
  EXPECT_EQ(error(""), "m.json: field 'channels' expected at least one channel, found none");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"column": "a"}}, {"motor": "M", "joint_angle": {"column": "b"}})"),
            "m.json: field 'channels[1].motor' expected a motor not named before, found 'M'");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"column": "a"}})", R"(, "delimiter": ";;")"),
            "m.json: field 'delimiter' expected a one-character string, found the string \";;\"");
  EXPECT_EQ(error(R"({"motor": "M", "joint_angle": {"column": "a"}})", R"(, "delimiter": "\"")"),
            "m.json: field 'delimiter' expected one character other than a quote or a line break, found '\"'");
  EXPECT_EQ(InputErrorOf([] {
              Mapping(R"({"agent": "P", "time": {"constant": 0}, "channels": [{"motor": "M", "joint_angle":
                          {"column": "a"}}]})");
            }),
            "m.json: field 'time' expected a column, found a constant");
  EXPECT_EQ(InputErrorOf([] {
              Mapping(R"({"agent": "A/B", "time": {"column": "t"}, "channels": [{"motor": "M", "joint_angle":
                          {"column": "a"}}]})");
            }),
            "m.json: field 'agent' expected an agent name without '/', found 'A/B'");
}

// docs/gap_measured_data.md's column-mapping example, read from the page as a reader would copy it (a copy kept here
// went stale while the page's example had 20 ms rows for a 10 ms rig and a motor 'Right/Hip' the A-Series lacks): it
// reads, and replays on its rig.
TEST(MeasuredRunTest, TheDocsColumnMappingExampleReadsAndReplaysOnItsRig) {
  const std::string doc = ReadTextFile(ORCS_SOURCE_DIR "/docs/gap_measured_data.md");
  const std::size_t example = doc.find("Example: the logger of a test stand");
  ASSERT_NE(example, std::string::npos);
  const auto block = [&](const std::string& fence, std::size_t from) {
    const std::size_t begin = doc.find('\n', doc.find(fence, from)) + 1;
    const std::size_t end = doc.find("```", begin);
    return std::pair{doc.substr(begin, end - begin), end + 3};
  };
  const auto [csv, after_csv] = block("```\n", example);
  const auto [json, after_json] = block("```json", after_csv);
  const ColumnMapping m = Mapping(json);
  const MeasuredRun run = ParseMeasuredRun(csv, "stand.csv", &m);
  EXPECT_THAT(run.motors, ElementsAre("Motor"));
  EXPECT_DOUBLE_EQ(run.step, 0.01);
  EXPECT_THAT(run.desired_angle.at("Motor"), ElementsAre(0.0, 18 * 0.29296875, 36 * 0.29296875));
  EXPECT_THAT(run.joint_angle.at("Motor"), ElementsAre(0.0, 2 * 0.29296875, 7 * 0.29296875));
  const std::vector<ValueAssignment> model;
  RigOptions pendulum;
  pendulum.kind = "pendulum";  // as the page's command line says
  EXPECT_NO_THROW(MakeReplayRun(MakeRig(pendulum, m.agent, model), run, model));
}

// On the A-Series a replay drives every motor: a log of two joints is refused with what to add.
TEST(MeasuredRunTest, AReplayOfAFewJointsOfTheASeriesSaysHowToCommandTheOthers) {
  const std::string csv = "# columns: time,/Sim/Humanoid/Right/Knee/DesiredAngle,/Sim/Humanoid/Right/Knee/DesiredTorque,"
                          "/Sim/Humanoid/Right/Knee/JointAngle\n0,0,1,0\n0.01,5,1,1\n0.02,10,1,3\n";
  const MeasuredRun run = ParseMeasuredRun(csv, "knee.csv");
  const std::vector<ValueAssignment> model;
  const std::string message = InputErrorOf([&] { MakeReplayRun(MakeRig(RigOptions{}, "Humanoid", model), run, model); });
  EXPECT_THAT(message, ::testing::HasSubstr("no column '/Sim/Humanoid/Waist/DesiredAngle'"));
  EXPECT_THAT(message, ::testing::HasSubstr("the run commands 1 of its 21 motors"));
  EXPECT_THAT(message, ::testing::HasSubstr(R"({"motor": "Waist", "desired_angle": {"constant": 0})"));
}

TEST(MeasuredRunTest, MappedColumnMissingFromTheHeaderNamesBothFiles) {
  const ColumnMapping m = Mapping(kLoggerMapping);
  const std::string csv = "t_ms;cmd_knee;position_knee;pos_hip\n0;1;2;3\n20;1;2;3\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(csv, "log.csv", &m); }),
            "log.csv: no column 'pos_knee' (named by m.json, field 'channels[0].joint_angle.column')");
  const std::string twice = "t_ms;cmd_knee;pos_knee;pos_hip;pos_knee\n0;1;2;3;4\n20;1;2;3;4\n";
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(twice, "log.csv", &m); }),
            "log.csv: column 'pos_knee' appears twice (fields 3 and 5), so m.json, field "
            "'channels[0].joint_angle.column' is ambiguous");
}

TEST(MeasuredRunTest, MappedRowErrorsNameLineAndTheRealColumn) {
  const ColumnMapping m = Mapping(kLoggerMapping);
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n0;1;2;3\n20;1;x;3\n", "l.csv", &m); }),
            "l.csv:3: column 'pos_knee': 'x' is not a finite number");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n0;1;2;3\n20;1;2\n", "l.csv", &m); }),
            "l.csv:3: expected 4 fields, found 3");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n5;1;2;3\n25;1;2;3\n", "l.csv", &m); }),
            "l.csv:2: column 't_ms': expected the first time to be 0 s, found 0.005 s");
  EXPECT_EQ(InputErrorOf([&] {
              ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n0;1;2;3\n20;1;2;3\n30;1;2;3\n", "l.csv", &m);
            }),
            "l.csv:4: column 't_ms': expected a uniform step of 0.02 s (that of the first two rows), found 0.01 s "
            "from 0.02 s to 0.03 s");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun("t_ms;cmd_knee;pos_knee;pos_hip\n", "l.csv", &m); }),
            "l.csv: no data rows");
}

// ---------------------------------------------------------------------------------------------------------
// Sets of runs

MeasuredRun RunOf(const std::string& source, const std::string& agent, double step) {
  MeasuredRun run;
  run.source = source;
  run.agent = agent;
  run.step = step;
  return run;
}

// ---------------------------------------------------------------------------------------------------------
// The servo's firmware gain (docs/gap_measured_data.md, "The firmware gain")

// The head of a real XL330 log (scenarios/data/xl330-pendulum/lift_and_drop_kp100.csv), two rows.
constexpr const char* kXl330Log =
    "# XL330 pendulum log: motor=xl330 load_mass_kg=0.49 load_distance_m=0.1 firmware_kp=100 supply_v=7.4 dt_s=0.005 "
    "trajectory=lift_and_drop\n"
    "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n"
    "0,0.00129535491,-0.791015625,0,3,7.3,29,1\n"
    "0.005,-0.000518284001,-0.791015625,0,3,7.3,29,0\n";

ColumnMapping Xl330Mapping(const std::string& gain) {
  return Mapping(R"({"agent": "Pendulum", "time": {"column": "time_s"}, "firmware_kp": )" + gain +
                 R"(, "channels": [{"motor": "Motor", "desired_angle": {"column": "goal_deg"},
                   "desired_torque": {"column": "torque_enable"}, "joint_angle": {"column": "position_deg"}}]})");
}

TEST(MeasuredRunTest, TheFirmwareGainComesFromAHeaderKeyAColumnOrAConstant) {
  const ColumnMapping header = Xl330Mapping(R"({"header": "firmware_kp"})");
  const MeasuredRun run = ParseMeasuredRun(kXl330Log, "kp100.csv", &header);
  EXPECT_EQ(FirmwareGain(run), 100.0);
  EXPECT_THAT(run.desired_torque.at("Motor"), ElementsAre(1.0, 0.0)) << "torque_enable is the torque";
  const ColumnMapping column = Xl330Mapping(R"({"column": "temperature_c"})");
  EXPECT_EQ(FirmwareGain(ParseMeasuredRun(kXl330Log, "kp.csv", &column)), 29.0);
  const ColumnMapping constant = Xl330Mapping(R"({"constant": 400})");
  EXPECT_EQ(FirmwareGain(ParseMeasuredRun(kXl330Log, "kp.csv", &constant)), 400.0);
  // An orcs log carries it as the column /Servo/FirmwareKp.
  const MeasuredRun native = ParseMeasuredRun(
      "# columns: time,/Sim/P/M/JointAngle,/Servo/FirmwareKp\n0,0,32\n0.01,1,32\n", "run.csv", nullptr);
  EXPECT_EQ(FirmwareGain(native), 32.0);
  EXPECT_FALSE(FirmwareGain(ParseMeasuredRun(kPendulumLog, "run.csv", nullptr)).has_value());
}

TEST(MeasuredRunTest, AFirmwareGainMissingFromTheHeaderOrChangingWithinARunIsOneLineNamingFileAndColumn) {
  const ColumnMapping header = Xl330Mapping(R"({"header": "firmware_kp"})");
  std::string without = kXl330Log;
  without.replace(without.find("firmware_kp=100"), 15, "gain=100");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(without, "kp.csv", &header); }),
            "kp.csv: no 'firmware_kp=' in the comment lines (named by m.json, field 'firmware_kp.header'): the servo's "
            "firmware gain is missing");
  std::string letters = kXl330Log;
  letters.replace(letters.find("firmware_kp=100"), 15, "firmware_kp=hi");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(letters, "kp.csv", &header); }),
            "kp.csv: header key 'firmware_kp': 'hi' is not a finite number");
  const ColumnMapping column = Xl330Mapping(R"({"column": "load"})");
  std::string changing = kXl330Log;
  changing.replace(changing.rfind(",3,7.3"), 6, ",4,7.3");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(changing, "kp.csv", &column); }),
            "kp.csv:4: load: the firmware gain changes within the run, from 3 (line 3) to 4; a run has one gain — "
            "split the log where it changes");
  EXPECT_EQ(InputErrorOf([&] {
              ParseMeasuredRun("# columns: time,/Sim/P/M/JointAngle,/Servo/FirmwareKp\n0,0,0\n0.01,1,0\n", "run.csv",
                               nullptr);
            }),
            "run.csv:2: /Servo/FirmwareKp: expected a positive firmware gain, found 0");
  EXPECT_EQ(InputErrorOf([&] { Xl330Mapping(R"({"header": "firmware_kp", "scale": 2})"); }),
            "m.json: field 'firmware_kp.scale' expected nothing beside \"header\", found the number 2");
  EXPECT_EQ(InputErrorOf([&] {
              Mapping(R"({"agent": "P", "time": {"column": "t"}, "channels": [{"motor": "M",
                        "joint_angle": {"header": "a"}}]})");
            }),
            "m.json: field 'channels[0].joint_angle.header' expected a column or a constant, found a header key");
}

// The winding temperature (docs/gap_measured_data.md, "The winding temperature"): a column, a constant or a header
// key like the gain; the replay takes the run's mean. Out of a servo's range it is one line naming file, line and
// column.
TEST(MeasuredRunTest, TheWindingTemperatureIsTheRunsMeanOfItsColumnAndOutOfRangeIsOneLine) {
  ColumnMapping mapping = Xl330Mapping(R"({"header": "firmware_kp"})");
  mapping.winding_temperature.emplace().column = "temperature_c";
  std::string warming = kXl330Log;
  warming.replace(warming.rfind(",7.3,29,"), 8, ",7.3,30,");
  const MeasuredRun run = ParseMeasuredRun(warming, "kp100.csv", &mapping);
  EXPECT_THAT(run.winding_temperature, ElementsAre(29.0, 30.0));
  EXPECT_EQ(WindingTemperature(run), 29.5);
  const ColumnMapping unmapped = Xl330Mapping(R"({"constant": 1})");
  EXPECT_FALSE(WindingTemperature(ParseMeasuredRun(kXl330Log, "kp.csv", &unmapped)).has_value()) << "not mapped";
  const MeasuredRun native = ParseMeasuredRun(
      "# columns: time,/Sim/P/M/JointAngle,/Servo/WindingTemperature\n0,0,40\n0.01,1,42\n", "run.csv", nullptr);
  EXPECT_EQ(WindingTemperature(native), 41.0);
  std::string kelvin = kXl330Log;
  kelvin.replace(kelvin.rfind(",7.3,29,"), 8, ",7.3,302,");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(kelvin, "kp.csv", &mapping); }),
            "kp.csv:4: temperature_c: expected a winding temperature of −50 … 200 °C, found 302");
}

// The supply voltage (docs/gap_measured_data.md, "The supply voltage"): mapped as "supply_voltage" (a column, a
// constant or a header key) or logged as /Servo/SupplyVoltage, it is kept per row, since the supply sags under
// load; a row outside 0 < V ≤ 60 V is one line naming file, line and column, and a misspelt key is still refused.
TEST(MeasuredRunTest, TheSupplyVoltageIsKeptPerRowAndOutsideZeroTo60VoltsIsOneLine) {
  const auto mapping = [](const std::string& voltage) {
    return Mapping(R"({"agent": "Pendulum", "time": {"column": "time_s"}, "firmware_kp": {"header": "firmware_kp"},
                       "supply_voltage": )" + voltage + R"(, "channels": [{"motor": "Motor",
                       "desired_angle": {"column": "goal_deg"}, "desired_torque": {"column": "torque_enable"},
                       "joint_angle": {"column": "position_deg"}}]})");
  };
  const ColumnMapping column = mapping(R"({"column": "input_volts"})");
  ASSERT_TRUE(column.supply_voltage.has_value());
  EXPECT_EQ(column.supply_voltage->column, "input_volts");
  const auto with_volts = [](const std::string& second_row) {
    std::string log = kXl330Log;
    log.replace(log.rfind(",7.3,29,"), 8, "," + second_row + ",29,");
    return log;
  };
  const MeasuredRun sagging = ParseMeasuredRun(with_volts("6.1"), "kp400.csv", &column);
  EXPECT_THAT(sagging.supply_voltage, ElementsAre(7.3, 6.1));
  EXPECT_EQ(sagging.supply_voltage_column, "input_volts");
  EXPECT_THAT(ParseMeasuredRun(with_volts("60"), "kp400.csv", &column).supply_voltage, ElementsAre(7.3, 60.0));
  const ColumnMapping header = mapping(R"({"header": "supply_v"})");
  EXPECT_THAT(ParseMeasuredRun(kXl330Log, "kp100.csv", &header).supply_voltage, ElementsAre(7.4, 7.4));
  const ColumnMapping unmapped = Xl330Mapping(R"({"header": "firmware_kp"})");
  EXPECT_THAT(ParseMeasuredRun(kXl330Log, "kp100.csv", &unmapped).supply_voltage, IsEmpty()) << "not mapped";
  const MeasuredRun native = ParseMeasuredRun(
      "# columns: time,/Sim/P/M/JointAngle,/Servo/SupplyVoltage\n0,0,7.4\n0.01,1,5.9\n", "run.csv", nullptr);
  EXPECT_THAT(native.supply_voltage, ElementsAre(7.4, 5.9));
  EXPECT_THAT(ParseMeasuredRun(kPendulumLog, "run.csv", nullptr).supply_voltage, IsEmpty());

  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(with_volts("0"), "kp.csv", &column); }),
            "kp.csv:4: input_volts: expected a supply voltage above 0 and at most 60 V, found 0");
  EXPECT_EQ(InputErrorOf([&] { ParseMeasuredRun(with_volts("75"), "kp.csv", &column); }),
            "kp.csv:4: input_volts: expected a supply voltage above 0 and at most 60 V, found 75");
  EXPECT_EQ(InputErrorOf([&] {
              ParseMeasuredRun("# columns: time,/Sim/P/M/JointAngle,/Servo/SupplyVoltage\n0,0,7400\n0.01,1,7400\n",
                               "run.csv", nullptr);
            }),
            "run.csv:2: /Servo/SupplyVoltage: expected a supply voltage above 0 and at most 60 V, found 7400");
  EXPECT_EQ(InputErrorOf([&] {
              Mapping(R"({"agent": "P", "time": {"column": "t"}, "supply_volts": {"column": "v"},
                        "channels": [{"motor": "M", "joint_angle": {"column": "a"}}]})");
            }),
            "m.json: field 'supply_volts' expected no such field (allowed: agent, time, channels, delimiter, "
            "firmware_kp, winding_temperature, supply_voltage, command_timing, accelerometers), found 'supply_volts'");
}

// A log that reads the state and then sends the commands (BAM's, the XL330's) says so with "command_timing":
// "from_row"; its row k's goal, torque flag and voltage are then row k+1's in orcs's timing, so the replay's
// firmware sees each goal one step later than with the default "until_row" (an orcs log's timing).
TEST(MeasuredRunTest, CommandsSentAfterTheRowsReadingActOneRowLater) {
  const std::string log =
      "# firmware_kp=400\n"
      "time_s,goal_deg,position_deg,torque_enable,input_volts\n"
      "0,1,0.5,1,7.4\n0.005,2,0.6,1,7.3\n0.01,3,0.7,0,7.2\n0.015,4,0.8,1,7.1\n";
  const auto mapping = [](const std::string& timing) {
    return Mapping(R"({"agent": "Pendulum", "time": {"column": "time_s"}, "supply_voltage": {"column": "input_volts"},
                       )" + timing + R"("channels": [{"motor": "Motor", "desired_angle": {"column": "goal_deg"},
                       "desired_torque": {"column": "torque_enable"}, "joint_angle": {"column": "position_deg"}}]})");
  };
  const ColumnMapping until_row = mapping("");
  const ColumnMapping from_row = mapping(R"("command_timing": "from_row", )");
  EXPECT_EQ(until_row.command_timing, CommandTiming::kUntilRow) << "the default";
  EXPECT_EQ(mapping(R"("command_timing": "until_row", )").command_timing, CommandTiming::kUntilRow);
  EXPECT_EQ(from_row.command_timing, CommandTiming::kFromRow);

  const MeasuredRun as_logged = ParseMeasuredRun(log, "run.csv", &until_row);
  EXPECT_THAT(as_logged.desired_angle.at("Motor"), ElementsAre(1, 2, 3, 4));
  const MeasuredRun shifted = ParseMeasuredRun(log, "run.csv", &from_row);
  EXPECT_THAT(shifted.desired_angle.at("Motor"), ElementsAre(1, 1, 2, 3));
  EXPECT_THAT(shifted.desired_torque.at("Motor"), ElementsAre(1, 1, 1, 0));
  EXPECT_THAT(shifted.supply_voltage, ElementsAre(7.4, 7.4, 7.3, 7.2));
  EXPECT_EQ(shifted.joint_angle, as_logged.joint_angle) << "the angles keep their rows";
  EXPECT_EQ(shifted.time, as_logged.time);
  // In the replay's keyframes, the step from row 0 to row 1 is driven by row 0's goal.
  const control::KeyframeRecord record = CommandsAsRecord(shifted, {"Motor"});
  ASSERT_EQ(record.frames.size(), 3u);
  EXPECT_THAT(record.frames[0].inputs, ElementsAre(1, 1));
  EXPECT_THAT(record.frames[2].inputs, ElementsAre(3, 0));
  EXPECT_EQ(record.frames[0].line, 3) << "row 0's goal, read from line 3, names that line in messages";
  EXPECT_EQ(record.frames[2].line, 5);
  EXPECT_EQ(CommandsAsRecord(as_logged, {"Motor"}).frames[0].line, 4) << "row 1's own line";

  EXPECT_EQ(InputErrorOf([&] { mapping(R"("command_timing": "before", )"); }),
            "m.json: field 'command_timing' expected \"until_row\" (a row's commands produced its state) or "
            "\"from_row\" (they act after it), found the string \"before\"");
  EXPECT_EQ(InputErrorOf([&] { mapping(R"("command_timing": 1, )"); }),
            "m.json: field 'command_timing' expected \"until_row\" or \"from_row\", found the number 1");
}

TEST(MeasuredRunTest, AnEmptyGoalIsALimpRowOnlyWhereTheTorqueEnableColumnSays0) {
  const ColumnMapping header = Xl330Mapping(R"({"header": "firmware_kp"})");
  const std::string head =
      "# firmware_kp=100\ntime_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n";
  const MeasuredRun run =
      ParseMeasuredRun(head + "0,5,0,0,0,7.4,30,1\n0.005,,-1,0,0,7.4,30,0\n0.01,,-2,0,0,7.4,30,0\n", "limp.csv", &header);
  EXPECT_THAT(run.desired_angle.at("Motor"), ElementsAre(5.0, 5.0, 5.0)) << "a limp servo keeps its last goal";
  EXPECT_THAT(run.desired_torque.at("Motor"), ElementsAre(1.0, 0.0, 0.0));
  EXPECT_EQ(InputErrorOf([&] {
              ParseMeasuredRun(head + "0,5,0,0,0,7.4,30,1\n0.005,,-1,0,0,7.4,30,1\n", "limp.csv", &header);
            }),
            "limp.csv:4: column 'goal_deg' is empty, but column 'torque_enable' says 1 (torque on): an empty goal is a "
            "limp segment only where a torque-enable column says 0 — map 'desired_torque' to the log's torque-enable "
            "column");
  const ColumnMapping constant_torque = Mapping(
      R"({"agent": "Pendulum", "time": {"column": "time_s"}, "channels": [{"motor": "Motor",
          "desired_angle": {"column": "goal_deg"}, "desired_torque": {"constant": 1},
          "joint_angle": {"column": "position_deg"}}]})");
  EXPECT_EQ(InputErrorOf([&] {
              ParseMeasuredRun(head + "0,5,0,0,0,7.4,30,1\n0.005,,-1,0,0,7.4,30,0\n", "limp.csv", &constant_torque);
            }),
            "limp.csv:4: column 'goal_deg' is empty, but the mapping gives its torque as a constant: an empty goal is "
            "a limp segment only where a torque-enable column says 0 — map 'desired_torque' to the log's "
            "torque-enable column");
}

TEST(MeasuredRunTest, RunsMustShareAgentAndStep) {
  EXPECT_NO_THROW(CheckRunsAgree({}));
  EXPECT_NO_THROW(CheckRunsAgree({RunOf("a.csv", "Humanoid", 0.01), RunOf("b.csv", "Humanoid", 0.01 + 5e-10)}));
  EXPECT_EQ(InputErrorOf([] {
              CheckRunsAgree({RunOf("a.csv", "Humanoid", 0.01), RunOf("b.csv", "Pendulum", 0.01)});
            }),
            "b.csv: measured run of agent 'Pendulum', but a.csv is of agent 'Humanoid': all measured runs must "
            "come from one rig");
  EXPECT_EQ(InputErrorOf([] {
              CheckRunsAgree({RunOf("a.csv", "P", 0.01), RunOf("b.csv", "P", 0.01), RunOf("c.csv", "P", 0.02)},
                             "holdout");
            }),
            "c.csv: holdout run with a time step of 0.02 s, but a.csv has 0.01 s: all holdout runs must share one "
            "time step");
  EXPECT_THAT(InputErrorOf([] { CheckRunsAgree({RunOf("a.csv", "P", 0.01), RunOf("b.csv", "P", 0.01 + 2e-9)}); }),
              HasSubstr("b.csv: measured run with a time step of"));
}

TEST(MeasuredRunTest, HoldoutRunsMustNotBeFitRuns) {
  const TempDir dir;
  const std::string a = dir.Write("a.csv", PendulumLog("0,0,1,0\n0.01,0,1,1\n"));
  const std::string b = dir.Write("b.csv", PendulumLog("0,0,1,0\n0.01,0,1,2\n"));
  const std::string copy_of_a = dir.Write("sub/copy.csv", PendulumLog("0,0,1,0\n0.01,0,1,1\n"));
  EXPECT_NO_THROW(CheckDisjoint({a}, {b}));
  EXPECT_NO_THROW(CheckDisjoint({}, {b}));
  const std::string a_again = (dir.path() / "sub" / ".." / "a.csv").string();
  EXPECT_EQ(InputErrorOf([&] { CheckDisjoint({b, a}, {a_again}); }),
            a_again + ": a holdout run is also a fit run: the same file as " + a);
  EXPECT_EQ(InputErrorOf([&] { CheckDisjoint({b, a}, {copy_of_a}); }),
            copy_of_a + ": a holdout run is also a fit run: the same contents as " + a);
  EXPECT_EQ(InputErrorOf([&] { CheckDisjoint({a}, {dir.PathOf("none.csv")}); }),
            dir.PathOf("none.csv") + ": cannot read the file: no such file");
}

TEST(MeasuredRunTest, HoldoutGivenByARelativePathIsTheSameFile) {
  const TempDir dir;
  const std::string a = dir.Write("a.csv", "x");
  const std::filesystem::path relative = std::filesystem::relative(a);
  EXPECT_EQ(InputErrorOf([&] { CheckDisjoint({a}, {relative.string()}); }),
            relative.string() + ": a holdout run is also a fit run: the same file as " + a);
}

// ---------------------------------------------------------------------------------------------------------
// Commands as a keyframe record

TEST(MeasuredRunTest, CommandsAsRecordCarriesRowIsInputsHalfAStepBeforeTheStepThatAppliesThem) {
  const MeasuredRun run = ParseMeasuredRun(kHumanoidLog + std::string("0.04,12,0.3,0.7,22,-22,0.03,0.8,2\n"), "h.csv");
  // Rig input order differs from column order.
  const control::KeyframeRecord record = CommandsAsRecord(run, {"Right/Knee", "Left/Knee"});
  EXPECT_EQ(record.source, "h.csv");
  EXPECT_EQ(record.layout, control::KeyframeLayout::kRaw);
  EXPECT_FALSE(record.layout_detected);
  EXPECT_EQ(record.motor_count, 2);
  ASSERT_EQ(record.frames.size(), 2u);  // rows 1 and 2; row 0 is the state after reset
  EXPECT_EQ(record.frames[0].time_ms, 0.0);  // t0 − step/2 < 0: clamped
  EXPECT_THAT(record.frames[0].inputs, ElementsAre(21.0, 0.9, -21.0, 0.6));
  EXPECT_EQ(record.frames[0].line, 3);
  EXPECT_DOUBLE_EQ(record.frames[1].time_ms, 10.0);  // (0.02 − 0.01) s
  EXPECT_THAT(record.frames[1].inputs, ElementsAre(22.0, 0.8, -22.0, 0.7));
  EXPECT_EQ(record.frames[1].line, 4);
}

TEST(MeasuredRunTest, CommandsAsRecordTakesEffectAtTheStepStartingAtTheRowBefore) {
  // A step of 1/30 s cannot be written exactly: keyframe i−1 (row i's inputs) must be reached at the start of
  // the step from t(i−1) to t(i), and not yet at the start of the step before, t(i−2).
  std::string rows;
  for (int i = 0; i < 100; ++i) {
    rows += text::FormatDouble(i / 30.0) + "," + std::to_string(i) + ",1," + std::to_string(-i) + "\n";
  }
  const MeasuredRun run = ParseMeasuredRun(PendulumLog(rows), "p.csv");
  const control::KeyframeRecord record = CommandsAsRecord(run, {"Motor"});
  ASSERT_EQ(record.frames.size(), 99u);
  for (size_t i = 1; i < run.time.size(); ++i) {
    const control::Keyframe& frame = record.frames[i - 1];
    EXPECT_EQ(frame.inputs.front(), static_cast<double>(i)) << "row " << i;
    EXPECT_NEAR(frame.time_ms, std::max(0.0, run.time[i - 1] - run.step / 2) * 1000.0, 1e-9) << "row " << i;
    EXPECT_LE(frame.time_ms, run.time[i - 1] * 1000.0) << "row " << i;
    if (i >= 2) {
      EXPECT_GT(frame.time_ms, run.time[i - 2] * 1000.0) << "row " << i;
    }
  }
}

TEST(MeasuredRunTest, CommandsAsRecordNamesTheMissingInputColumn) {
  const MeasuredRun run = ParseMeasuredRun(kHumanoidLog, "h.csv");
  EXPECT_THAT(InputErrorOf([&] { CommandsAsRecord(run, {"Right/Knee", "Head/Pan"}); }),
              ::testing::StartsWith("h.csv: no column '/Sim/Humanoid/Head/Pan/DesiredAngle': a replay drives every "
                                    "motor of Humanoid, and the run commands 1 of its 2 motors"));
  MeasuredRun torque_lost = run;
  torque_lost.desired_torque.erase("Left/Knee");
  EXPECT_THAT(InputErrorOf([&] { CommandsAsRecord(torque_lost, {"Left/Knee"}); }),
              ::testing::StartsWith("h.csv: no column '/Sim/Humanoid/Left/Knee/DesiredTorque'"));
}

TEST(MeasuredRunTest, MotorColumnJoinsAgentMotorAndQuantity) {
  EXPECT_EQ(MotorColumn("Humanoid", "Right/Knee", "JointAngle"), "/Sim/Humanoid/Right/Knee/JointAngle");
}

}  // namespace
}  // namespace orcs::identify
