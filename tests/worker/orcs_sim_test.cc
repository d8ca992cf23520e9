// Tests of the orcs-sim program: they run the real binary and look at its exit code, stdout, stderr and files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::ProcessResult;
using test_support::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

const std::string kOrcsSim = std::string(ORCS_BINARY_DIR) + "/bin/orcs-sim";
const std::string kExample = std::string(ORCS_SOURCE_DIR) + "/scenarios/environments/example.xml";
constexpr double kSphereRadius = 0.05;

// A CSV log as orcs-sim writes it: comment lines, a "# columns: " line, rows of numbers.
struct Csv {
  std::vector<std::string> comments;  // without the leading "# "
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  int Column(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
  }
};

std::vector<std::string> SplitAt(const std::string& text, char separator) {
  std::vector<std::string> fields;
  std::stringstream stream(text);
  std::string field;
  while (std::getline(stream, field, separator)) fields.push_back(field);
  return fields;
}

// Parses `path`; fails the test (and returns what it has) on anything malformed.
Csv ReadCsv(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("# columns: ", 0) == 0) {
      EXPECT_TRUE(csv.columns.empty()) << "second column line";
      csv.columns = SplitAt(line.substr(11), ',');
    } else if (line.rfind("# ", 0) == 0) {
      EXPECT_TRUE(csv.columns.empty()) << "comment after the column line: " << line;
      csv.comments.push_back(line.substr(2));
    } else {
      std::vector<double> row;
      for (const std::string& field : SplitAt(line, ',')) {
        size_t used = 0;
        row.push_back(std::stod(field, &used));
        EXPECT_EQ(used, field.size()) << "not a number: " << field;
      }
      EXPECT_EQ(row.size(), csv.columns.size()) << line;
      csv.rows.push_back(row);
    }
  }
  return csv;
}

class OrcsSimTest : public ::testing::Test {
 protected:
  static ProcessResult Run(std::initializer_list<std::string> arguments) {
    std::vector<std::string> argv{kOrcsSim};
    argv.insert(argv.end(), arguments);
    return test_support::RunProcess(argv);
  }

  // Runs the logging example with extra arguments and returns the CSV it wrote.
  Csv RunLoggedExample(std::initializer_list<std::string> extra) {
    std::vector<std::string> argv{kOrcsSim,
                                  "-env",
                                  kExample,
                                  "--duration",
                                  "2",
                                  "--log",
                                  ".*SecondSphere/Position",
                                  "--out",
                                  dir_.PathOf("s.csv")};
    argv.insert(argv.end(), extra);
    const ProcessResult result = test_support::RunProcess(argv);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return ReadCsv(dir_.PathOf("s.csv"));
  }

  TempDir dir_;
};

// A bad-input run: exit code 2, no signal, exactly one line on stderr, no crash text.
void ExpectBadInput(const ProcessResult& result) {
  EXPECT_EQ(result.signal, 0) << "killed by signal " << result.signal;
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << "one line on stderr:\n" << result.err;
  EXPECT_TRUE(!result.err.empty() && result.err.back() == '\n') << result.err;
  EXPECT_THAT(result.err, StartsWith("orcs-sim: "));
  EXPECT_THAT(result.err, Not(HasSubstr("terminate")));
  EXPECT_THAT(result.err, Not(HasSubstr("Aborted")));
}

// ---------------------------------------------------------------------------------------------------------
// Runs that work

TEST_F(OrcsSimTest, LogsTheFallingSphereToCsv) {
  const ProcessResult result =
      Run({"-env", kExample, "--duration", "2", "--log", ".*SecondSphere/Position", "--out", dir_.PathOf("s.csv")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.signal, 0);
  EXPECT_THAT(result.out, HasSubstr("200 steps"));
  const std::string text = dir_.Read("s.csv");
  EXPECT_THAT(text, HasSubstr("\n# columns: time,/Sim/SecondSphere/Position.x,/Sim/SecondSphere/Position.y,"
                              "/Sim/SecondSphere/Position.z\n"));
  const Csv csv = ReadCsv(dir_.PathOf("s.csv"));
  ASSERT_EQ(csv.columns.size(), 4u);
  EXPECT_EQ(csv.columns[0], "time");
  const int x = csv.Column("/Sim/SecondSphere/Position.x");
  const int y = csv.Column("/Sim/SecondSphere/Position.y");
  const int z = csv.Column("/Sim/SecondSphere/Position.z");
  ASSERT_GE(x, 0);
  ASSERT_GE(y, 0);
  ASSERT_GE(z, 0);
  ASSERT_EQ(csv.rows.size(), 201u);  // t = 0 and 200 steps of 0.01 s

  EXPECT_EQ(csv.rows.front()[0], 0.0);
  EXPECT_EQ(csv.rows.front()[y], 0.5);
  EXPECT_EQ(csv.rows[1][0], 0.01);
  EXPECT_EQ(csv.rows.back()[0], 2.0);
  // Falls: strictly downwards through the first 0.2 s, at about g.
  for (size_t i = 1; i <= 20; ++i) EXPECT_LT(csv.rows[i][y], csv.rows[i - 1][y]) << "row " << i;
  EXPECT_NEAR(csv.rows[20][y], 0.5 - 0.5 * 9.81 * 0.2 * 0.2, 0.015);
  // Rests on the floor at its radius, still for the last half second.
  EXPECT_NEAR(csv.rows.back()[y], kSphereRadius, 0.002);
  double lowest = INFINITY;
  double highest = -INFINITY;
  for (size_t i = csv.rows.size() - 50; i < csv.rows.size(); ++i) {
    lowest = std::min(lowest, csv.rows[i][y]);
    highest = std::max(highest, csv.rows[i][y]);
  }
  EXPECT_LT(highest - lowest, 1e-3);
  // Straight down: x and z stay put.
  EXPECT_NEAR(csv.rows.back()[x], -0.3, 1e-6);
  EXPECT_NEAR(csv.rows.back()[z], 0.3, 1e-6);
  // The comments say what ran.
  EXPECT_THAT(csv.comments, ::testing::Contains(HasSubstr("example.xml")));
  EXPECT_THAT(csv.comments, ::testing::Contains("seed: 0"));
  // Nothing but the finished file is left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_.path()), fs::directory_iterator()), 1);
}

TEST_F(OrcsSimTest, PrintValuesPrintsPathEqualsValueLines) {
  const ProcessResult result = Run({"-env", kExample, "--print-values", "/Sim/SecondSphere/.*"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::map<std::string, std::string> values;
  for (const std::string& line : SplitAt(result.out, '\n')) {
    const size_t equals = line.find('=');
    ASSERT_NE(equals, std::string::npos) << line;
    EXPECT_THAT(line, StartsWith("/Sim/SecondSphere/"));
    values[line.substr(0, equals)] = line.substr(equals + 1);
  }
  EXPECT_EQ(values["/Sim/SecondSphere/Mass"], "0.1");
  EXPECT_EQ(values["/Sim/SecondSphere/Radius"], "0.05");
  EXPECT_EQ(values["/Sim/SecondSphere/Position"], "(-0.3,0.5,0.3)");
  EXPECT_EQ(values["/Sim/SecondSphere/Material"], "ABS");
  EXPECT_EQ(values["/Sim/SecondSphere/Dynamic"], "T");
  EXPECT_EQ(values["/Sim/SecondSphere/Color"], "(255,0,0,255)");
  EXPECT_EQ(values.count("/Sim/Box/Position"), 0u);
}

TEST_F(OrcsSimTest, DescribePrintsTheWorldAsJson) {
  const ProcessResult result = Run({"-env", kExample, "--describe"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  nlohmann::json world;
  ASSERT_NO_THROW(world = nlohmann::json::parse(result.out)) << result.out;
  EXPECT_EQ(world["environment"], kExample);

  const nlohmann::json& bodies = world["bodies"];
  ASSERT_TRUE(bodies.is_array());
  // The floor, two objects, and 24 bodies of each A-Series: the default Humanoid, to which the original added the
  // file's SecondASeries.
  ASSERT_EQ(bodies.size(), 3u + 2u * 24u);
  EXPECT_EQ(bodies[3]["name"], "Humanoid/Right/Foot");
  EXPECT_EQ(bodies[3u + 24u]["name"], "SecondASeries/Right/Foot");
  EXPECT_EQ(bodies[0]["name"], "Floor");
  EXPECT_EQ(bodies[0]["shape"], "plane");
  EXPECT_EQ(bodies[0]["material"], "PVC");
  EXPECT_EQ(bodies[0]["dynamic"], false);

  EXPECT_EQ(bodies[1]["name"], "Box");
  EXPECT_EQ(bodies[1]["shape"], "box");
  EXPECT_EQ(bodies[1]["dynamic"], false);
  EXPECT_EQ(bodies[1]["mass"], 0.0);
  EXPECT_EQ(bodies[1]["size"], nlohmann::json({0.2, 0.2, 0.2}));
  EXPECT_EQ(bodies[1]["material"], "Wood");

  EXPECT_EQ(bodies[2]["name"], "SecondSphere");
  EXPECT_EQ(bodies[2]["shape"], "sphere");
  EXPECT_EQ(bodies[2]["dynamic"], true);
  EXPECT_EQ(bodies[2]["mass"], 0.1);
  EXPECT_EQ(bodies[2]["size"], nlohmann::json({0.05}));
  EXPECT_EQ(bodies[2]["material"], "ABS");

  EXPECT_EQ(world["joints"].size(), 2u * (21u + 2u));  // each robot's motorised hinges and fixed joints
  const nlohmann::json& agents = world["agents"];
  ASSERT_EQ(agents.size(), 2u);
  EXPECT_EQ(agents[0]["name"], "Humanoid");
  EXPECT_EQ(agents[0]["position"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(agents[1]["name"], "SecondASeries");
  EXPECT_EQ(agents[1]["type"], "ASeries");
  EXPECT_EQ(agents[1]["position"], nlohmann::json({0.5, 0.001, -0.5}));
  // spec/aseries.md §4c and §9a: 21 motors in motor order with their ranges; 2.3844 kg within 1 %.
  const nlohmann::json& motors = agents[0]["motors"];
  ASSERT_EQ(motors.size(), 21u);
  EXPECT_EQ(motors[0]["name"], "Waist");
  EXPECT_EQ(motors[0]["range"], nlohmann::json({0.0, 150.0}));
  EXPECT_EQ(motors[13]["name"], "Right/Knee");
  EXPECT_EQ(motors[20]["name"], "Head/Tilt");
  EXPECT_NEAR(motors[20]["range"][0].get<double>(), -95.0, 1e-9);
  EXPECT_NEAR(agents[0]["mass"].get<double>(), 2.3844, 0.01 * 2.3844);
}

// --export-mjcf writes what the MuJoCo engine compiles: every body, joint and motor of the world, by name, and the
// exclusion list the engine applies per contact.
TEST_F(OrcsSimTest, ExportMjcfWritesTheWorldAsAMujocoModel) {
  const std::string out = dir_.PathOf("world.xml");
  const ProcessResult result = Run({"-env", kExample, "--export-mjcf", out});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::ifstream file(out);
  const std::string mjcf((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_THAT(mjcf, HasSubstr("<mujoco model=\"orcs\">"));
  EXPECT_THAT(mjcf, HasSubstr("<body name=\"SecondSphere\""));
  EXPECT_THAT(mjcf, HasSubstr("<body name=\"SecondASeries/Right/Foot\""));
  EXPECT_THAT(mjcf, HasSubstr("<joint name=\"SecondASeries/Waist\""));
  EXPECT_THAT(mjcf, HasSubstr("name=\"motor:SecondASeries/Head/Tilt\""));
  EXPECT_THAT(mjcf, HasSubstr("name=\"Box#0\""));  // a static object's geom
  // The suppression list (spec/aseries.md §3b), so that raw MuJoCo moves the robot as orcs does.
  EXPECT_THAT(mjcf, HasSubstr("<exclude body1=\"SecondASeries/Middle/HeadBase\" body2=\"SecondASeries/Middle/Head\"/>"));
}

TEST_F(OrcsSimTest, ExportMjcfToAnUnwritablePathIsOneLine) {
  ExpectBadInput(Run({"-env", kExample, "--export-mjcf", dir_.PathOf("no/such/dir/world.xml")}));
}

TEST_F(OrcsSimTest, DescribeShowsInitialValueChanges) {
  const std::string ival = dir_.Write("heavy.val", "/Sim/SecondSphere/Mass=2.5\n/Sim/Box/Width=0.4\n");
  const ProcessResult result = Run({"-env", kExample, "-ival", ival, "--describe"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json world = nlohmann::json::parse(result.out);
  EXPECT_EQ(world["bodies"][2]["mass"], 2.5);
  EXPECT_EQ(world["bodies"][1]["size"], nlohmann::json({0.4, 0.2, 0.2}));
}

// The robot's bodies are values too (docs/model.md, "The robot's values"): a foot's mass, from an initial value
// file (before the build) or a value file (after it, applied at the reset before the description), is the
// robot's total mass in --describe, and the foot's.
TEST_F(OrcsSimTest, DescribeShowsARobotFootsMassFromEitherValueFile) {
  const auto describe = [&](std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), kOrcsSim);
    arguments.push_back("--describe");
    const ProcessResult result = test_support::RunProcess(arguments);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return nlohmann::json::parse(result.out);
  };
  const auto foot_mass = [](const nlohmann::json& world) {
    for (const nlohmann::json& body : world["bodies"]) {
      if (body["name"] == "Humanoid/Right/Foot") return body["mass"].get<double>();
    }
    return -1.0;
  };
  const std::string heavy = dir_.Write("heavy_foot.val", "/Sim/Humanoid/Right/Foot/Mass=0.5\n");
  const nlohmann::json plain = describe({});
  const nlohmann::json initial = describe({"-ival", heavy});
  const nlohmann::json later = describe({"-val", heavy});
  const double added = 0.5 - 0.064219;  // the main box's mass replaced (model/aseries/aseries_morphology.json)
  EXPECT_NEAR(initial["agents"][0]["mass"].get<double>(), plain["agents"][0]["mass"].get<double>() + added, 1e-12);
  EXPECT_NEAR(foot_mass(initial), foot_mass(plain) + added, 1e-12);
  EXPECT_EQ(later["agents"][0]["mass"], initial["agents"][0]["mass"]);
}

// --export-robot writes the robot with the value files' changes as a robot file; an environment naming that file
// builds the same robot (the same total mass in --describe) without the value file.
TEST_F(OrcsSimTest, AnExportedRobotFileLoadsAsTheRobotTheValueFilesMade) {
  const std::string heavy = dir_.Write("heavy_foot.val", "/Sim/Humanoid/Right/Foot/Mass=0.5\n");
  ASSERT_EQ(Run({"-val", heavy, "--export-robot", dir_.PathOf("heavy.json")}).exit_code, 0);
  const nlohmann::json robot = nlohmann::json::parse(dir_.Read("heavy.json"));
  EXPECT_EQ(robot["format"], "orcs-aseries-morphology");
  EXPECT_EQ(robot["bodies"][0]["name"], "Right/Foot");
  EXPECT_EQ(robot["bodies"][0]["mass"], 0.5);
  const std::string environment = dir_.Write("heavy.xml", "<?xml version=\"1.0\"?>\n<ORCS version=\"1.0\">\n  <Agent>\n"
                                                          "    <ASeries name=\"Humanoid\" file=\"heavy.json\"/>\n"
                                                          "  </Agent>\n</ORCS>\n");
  const ProcessResult from_file = Run({"-env", environment, "--describe"});
  const ProcessResult from_values = Run({"-val", heavy, "--describe"});
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  ASSERT_EQ(from_values.exit_code, 0) << from_values.err;
  EXPECT_EQ(nlohmann::json::parse(from_file.out)["agents"][0]["mass"],
            nlohmann::json::parse(from_values.out)["agents"][0]["mass"]);
}

TEST_F(OrcsSimTest, InitialValueFileMovesTheStart) {
  const std::string ival = dir_.Write("start.val", "# start higher\n/Sim/SecondSphere/Position=(-0.3,1,0.3)\n");
  const Csv csv = RunLoggedExample({"-ival", ival});
  const int y = csv.Column("/Sim/SecondSphere/Position.y");
  ASSERT_GE(y, 0);
  ASSERT_FALSE(csv.rows.empty());
  EXPECT_EQ(csv.rows.front()[y], 1.0);
  EXPECT_LT(csv.rows[1][y], 1.0);
  EXPECT_NEAR(csv.rows.back()[y], kSphereRadius, 0.002);
}

TEST_F(OrcsSimTest, ValueFileHalvingTheTimeStepDoublesTheRows) {
  const Csv normal = RunLoggedExample({});
  const std::string val = dir_.Write("fine.val", "/Simulation/TimeStepSize=0.005\n");
  const Csv fine = RunLoggedExample({"-val", val});
  EXPECT_EQ(normal.rows.size(), 201u);
  ASSERT_EQ(fine.rows.size(), 401u);
  EXPECT_EQ(fine.rows[1][0], 0.005);
  EXPECT_EQ(fine.rows.back()[0], 2.0);
}

TEST_F(OrcsSimTest, DurationCountsIterationsPerStep) {
  const std::string val = dir_.Write("twice.val", "/Simulation/IterationsPerStep=2\n");
  const Csv csv = RunLoggedExample({"-val", val});
  ASSERT_EQ(csv.rows.size(), 101u);  // 100 steps of 2 × 0.01 s
  EXPECT_EQ(csv.rows.back()[0], 2.0);
}

TEST_F(OrcsSimTest, LongOptionSpellingsWorkToo) {
  const std::string ival = dir_.Write("start.val", "/Sim/SecondSphere/Position=(-0.3,1,0.3)\n");
  const ProcessResult result = Run({"--env", kExample, "--ival", ival, "--print-values", ".*SecondSphere/Position"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "/Sim/SecondSphere/Position=(-0.3,1,0.3)\n");
}

TEST_F(OrcsSimTest, DefaultRunStandsTheASeriesForTenSecondsAndSummarises) {
  const ProcessResult result = Run({});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("simulated 10.000 s in 1000 steps"));
  EXPECT_THAT(result.out, HasSubstr("wall time"));
  EXPECT_THAT(result.out, HasSubstr("real-time factor"));
}

// Issue 22: the original's example environment from its manual, unchanged, makes a world of two robots — the
// default A-Series and the file's SecondASeries — and runs; -nogui, the original's flag, is accepted. Both robots
// stand through the run (their heads at standing height at its end).
TEST_F(OrcsSimTest, TheManualsExampleRunsWithBothRobotsStanding) {
  const ProcessResult result = Run({"-env", kExample, "-nogui", "--duration", "2", "--log", ".*/Middle/Head/Position",
                                    "--out", dir_.PathOf("heads.csv")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const Csv csv = ReadCsv(dir_.PathOf("heads.csv"));
  for (const char* robot : {"Humanoid", "SecondASeries"}) {
    const int y = csv.Column(std::string("/Sim/") + robot + "/Middle/Head/Position.y");
    ASSERT_GE(y, 0) << robot << " is not in the world";
    EXPECT_GT(csv.rows.back()[static_cast<std::size_t>(y)], 0.3) << robot << "'s head at the end, m";
  }
  ExpectBadInput(Run({"-gui", "-nogui"}));
}

// Issue 22, item 11: the original's fitted motor set (spec §6e, Set B) ships as a value file; loaded, it sets
// every /AngularMotor value to the spec's and the default robot stands with it.
TEST_F(OrcsSimTest, TheOriginalsFittedMotorSetLoadsAndTheRobotStandsWithIt) {
  const std::string fitted = std::string(ORCS_SOURCE_DIR) + "/scenarios/values/dynamixel_fitted.val";
  const ProcessResult values = Run({"-val", fitted, "--print-values", "/AngularMotor/.*"});
  ASSERT_EQ(values.exit_code, 0) << values.err;
  EXPECT_THAT(values.out, HasSubstr("/AngularMotor/PID/Integral=18.2368306244975\n"));
  EXPECT_THAT(values.out, HasSubstr("/AngularMotor/FMaxFactor=1.16320990542266\n"));
  EXPECT_THAT(values.out, HasSubstr("/AngularMotor/DynamicFrictionOffset=0.19221690480294\n"));
  const ProcessResult run = Run({"-val", fitted, "--duration", "3", "--log", ".*Middle/Head/Position", "--out",
                                 dir_.PathOf("fitted.csv")});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Csv csv = ReadCsv(dir_.PathOf("fitted.csv"));
  const int y = csv.Column("/Sim/Humanoid/Middle/Head/Position.y");
  ASSERT_GE(y, 0);
  EXPECT_NEAR(csv.rows.back()[static_cast<std::size_t>(y)], 0.4037, 0.01) << "head height after 3 s, m";
}

// Issue 22, item 8: the torque-control model ships as a value file. On the pendulum rig (a 0.5 kg pole, gravity
// torque m·g·d = 0.736 N·m level) a constant torque command holds the pole where gravity balances it, within the
// band the LuGre stiction (0.05 N·m) leaves, on the side the torque points to.
TEST_F(OrcsSimTest, TheTorqueControlModelHoldsThePendulumWhereGravityBalancesTheCommandedTorque) {
  const std::string model = std::string(ORCS_SOURCE_DIR) + "/scenarios/values/torque_control_model.val";
  const std::string rig = std::string(ORCS_SOURCE_DIR) + "/scenarios/environments/pendulum.xml";
  constexpr double kFullTorque = 1.04803939, kGravity = 0.736, kStiction = 0.05;  // N·m
  // 0.45 N·m for 3 s, then −0.3 N·m: raw DesiredTorque = torque / FMaxFactor.
  const std::string record = dir_.Write("torque.csv", "# layout: raw\n0,0," + std::to_string(0.45 / kFullTorque) +
                                                          "\n3000,0," + std::to_string(-0.3 / kFullTorque) + "\n");
  const ProcessResult run = Run({"-env", rig, "-val", model, "-play", "Pendulum", record, "--duration", "6", "--log",
                                 "/Sim/Pendulum/Motor/JointAngle", "--out", dir_.PathOf("torque.log.csv")});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Csv csv = ReadCsv(dir_.PathOf("torque.log.csv"));
  const int angle = csv.Column("/Sim/Pendulum/Motor/JointAngle");
  ASSERT_GE(angle, 0);
  const auto degrees_at = [&](double torque) { return std::asin(torque / kGravity) * 180.0 / M_PI; };
  const double held_up = csv.rows[290][static_cast<std::size_t>(angle)];  // 2.9 s
  const double held_down = csv.rows.back()[static_cast<std::size_t>(angle)];
  EXPECT_GT(held_up, degrees_at(0.45 - kStiction) - 1.0);
  EXPECT_LT(held_up, degrees_at(0.45 + kStiction) + 1.0);
  EXPECT_LT(held_down, degrees_at(-0.3 + kStiction) + 1.0);
  EXPECT_GT(held_down, degrees_at(-0.3 - kStiction) - 1.0);
}

// Issue 22, item 5: -ival sets the motor model's values before the world is built, as the original's did.
TEST_F(OrcsSimTest, InitialValueFilesSetTheMotorModel) {
  const std::string ival = dir_.Write("motor.val", "/AngularMotor/PID/Proportional=25\n/AngularMotor/MaxVelocity=3\n");
  const ProcessResult result = Run({"-ival", ival, "--print-values", "/AngularMotor/(PID/Proportional|MaxVelocity)"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("/AngularMotor/PID/Proportional=25\n"));
  EXPECT_THAT(result.out, HasSubstr("/AngularMotor/MaxVelocity=3\n"));
  // And they take effect: motors of a hundredth of their torque cannot hold the robot up.
  const std::string weak = dir_.Write("weak.val", "/AngularMotor/FMaxFactor=0.01\n");
  ASSERT_EQ(Run({"-ival", weak, "--duration", "2", "--log", ".*Middle/Head/Position", "--out", dir_.PathOf("w.csv")})
                .exit_code,
            0);
  const Csv csv = ReadCsv(dir_.PathOf("w.csv"));
  const int y = csv.Column("/Sim/Humanoid/Middle/Head/Position.y");
  ASSERT_GE(y, 0);
  EXPECT_LT(csv.rows.back()[static_cast<std::size_t>(y)], 0.3) << "the weak robot's head after 2 s, m";
  // In the empty world there is no motor, and the path is unknown there: refused with --strict.
  ExpectBadInput(Run({"-env", "scenarios/environments/empty.xml", "-ival", ival, "--strict"}));
}

TEST_F(OrcsSimTest, RunsTheEmptyEnvironment) {
  const ProcessResult result = Run({"-env", "scenarios/environments/empty.xml", "--duration", "0.5"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("50 steps"));
}

TEST_F(OrcsSimTest, HelpExitsZero) {
  const ProcessResult result = Run({"--help"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("--env"));
  EXPECT_THAT(result.out, HasSubstr("--duration"));
  EXPECT_THAT(result.out, HasSubstr("--log"));
}

// ---------------------------------------------------------------------------------------------------------
// Bad input: exit 2 and one line naming the file and line (or the option).

TEST_F(OrcsSimTest, MalformedXml) {
  const std::string env = dir_.Write("bad.xml",
                                     "<ORCS version=\"1.0\">\n"
                                     "  <Environment>\n"
                                     "    <object type=\"box\" name=\"B\" position=\"(0,0,0)\" dimension=\"(1,1,1)\">\n"
                                     "  </Environment>\n"
                                     "</ORCS>\n");
  const ProcessResult result = Run({"-env", env});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(env + ":3: "));
  EXPECT_THAT(result.err, HasSubstr("malformed XML"));
}

TEST_F(OrcsSimTest, UnknownAttribute) {
  const std::string env = dir_.Write("bad.xml",
                                     "<ORCS version=\"1.0\">\n"
                                     "  <Environment>\n"
                                     "\n"
                                     "    <object type=\"box\" name=\"B\" position=\"(0,0,0)\" dimension=\"(1,1,1)\" "
                                     "weight=\"3\"/>\n"
                                     "  </Environment>\n"
                                     "</ORCS>\n");
  const ProcessResult result = Run({"-env", env});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(env + ":4: "));
  EXPECT_THAT(result.err, HasSubstr("unknown attribute 'weight'"));
}

TEST_F(OrcsSimTest, ValueFileLineWithoutEquals) {
  const std::string ival = dir_.Write("bad.val", "# fine\n/Sim/SecondSphere/Mass 0.2\n");
  const ProcessResult result = Run({"-env", kExample, "-ival", ival});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(ival + ":2: "));
  EXPECT_THAT(result.err, HasSubstr("path=value"));
}

TEST_F(OrcsSimTest, UnknownPathInInitialValueFileIsRefusedWithStrict) {
  const std::string ival = dir_.Write("bad.val", "/Sim/SecondSphere/Mass=0.2\n\n/Sim/ThirdSphere/Mass=0.2\n");
  const ProcessResult result = Run({"-env", kExample, "-ival", ival, "--strict"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(ival + ":3: "));
  EXPECT_THAT(result.err, HasSubstr("unknown repository path '/Sim/ThirdSphere/Mass'"));
}

TEST_F(OrcsSimTest, UnknownPathInValueFileIsRefusedWithStrict) {
  const std::string val = dir_.Write("bad.val", "/Simulation/TimeStepSiz=0.005\n");
  const ProcessResult result = Run({"-env", kExample, "-val", val, "--strict"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(val + ":1: "));
  EXPECT_THAT(result.err, HasSubstr("/Simulation/TimeStepSiz"));
}

// A value file as the original saved it, with its GUI's and cameras' values beside the simulation's: it loads, the
// values orcs has are set, the others are named in one warning; --strict refuses the file at its first such line.
TEST_F(OrcsSimTest, AnOriginalValueFileWithGuiAndCameraValuesLoadsWithOneWarningAndStrictRefusesIt) {
  const std::string val = dir_.Write("language_game.val",
                                     "#ORCS Values\n#Saved at: 2008-05-14 10:21:07\n"
                                     "/GUI/MainWindow/Width=800\n"
                                     "/Sim/SecondSphere/Mass=0.3\n"
                                     "/Camera/Main/Position=(0,0.5,1.2)\n"
                                     "/Plugins/MotionEditor/Visible=F\n"
                                     "/Simulation/TimeStepSiz=0.005\n");
  const ProcessResult loaded = Run({"-env", kExample, "-val", val, "--print-values", "/Sim/SecondSphere/Mass"});
  ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
  EXPECT_THAT(loaded.out, HasSubstr("/Sim/SecondSphere/Mass=0.3"));
  std::size_t warnings = 0;
  for (std::size_t at = loaded.err.find("warning:"); at != std::string::npos; at = loaded.err.find("warning:", at + 1)) {
    ++warnings;
  }
  EXPECT_EQ(warnings, 1u) << loaded.err;
  EXPECT_THAT(loaded.err, HasSubstr("ignored 4 value(s)"));
  EXPECT_THAT(loaded.err, HasSubstr("/GUI/MainWindow/Width (" + val + ":3)"));
  EXPECT_THAT(loaded.err, HasSubstr("/Camera/Main/Position (" + val + ":5)"));
  EXPECT_THAT(loaded.err, HasSubstr("/Plugins/MotionEditor/Visible (" + val + ":6)"));
  EXPECT_THAT(loaded.err, HasSubstr("unknown to orcs: /Simulation/TimeStepSiz (" + val + ":7)"));
  const ProcessResult strict = Run({"-env", kExample, "-val", val, "--strict", "--print-values", "/Sim/.*"});
  ExpectBadInput(strict);
  EXPECT_THAT(strict.err, HasSubstr(val + ":3: unknown repository path '/GUI/MainWindow/Width'"));
}

TEST_F(OrcsSimTest, BadValueInValueFile) {
  const std::string val = dir_.Write("bad.val", "/Simulation/TimeStepSize=fast\n");
  const ProcessResult result = Run({"-env", kExample, "-val", val});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(val + ":1: "));
  EXPECT_THAT(result.err, HasSubstr("'fast'"));
}

TEST_F(OrcsSimTest, TimeStepOutsideItsRangeInValueFile) {
  for (const char* step : {"0", "-0.01", "1e-300", "1e300"}) {
    SCOPED_TRACE(step);
    const std::string val = dir_.Write("zero.val", std::string("/Simulation/TimeStepSize=") + step + "\n");
    const ProcessResult result = Run({"-env", kExample, "-val", val, "--duration", "1"});
    ExpectBadInput(result);
    EXPECT_THAT(result.err, HasSubstr(val + ":1: "));
    EXPECT_THAT(result.err, HasSubstr("/Simulation/TimeStepSize"));
    EXPECT_THAT(result.err, HasSubstr("a number from 1e-05 to 0.1"));
  }
}

TEST_F(OrcsSimTest, NonPositiveIterationsInValueFile) {
  const std::string val = dir_.Write("zero.val", "/Simulation/IterationsPerStep=0\n");
  const ProcessResult result = Run({"-env", kExample, "-val", val});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("/Simulation/IterationsPerStep"));
}

TEST_F(OrcsSimTest, BadPhysicsParameterDuringTheRunIsOneLine) {
  const std::string val = dir_.Write("zero.val", "/Simulation/ODE/QuickStepIterations=0\n");
  const ProcessResult result = Run({"-env", kExample, "-val", val, "--duration", "0.1"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("/Simulation/ODE/QuickStepIterations"));
}

TEST_F(OrcsSimTest, UnknownEngineInValueFile) {
  const std::string val = dir_.Write("engine.val", "/Simulation/Engine=Bullet\n");
  const ProcessResult result = Run({"-env", kExample, "-val", val});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(val + ":1: /Simulation/Engine: expected one of ODE, MuJoCo, found 'Bullet'"));
}

TEST_F(OrcsSimTest, AMujocoSettingOnTheOdeEngineAndTheReverse) {
  const std::string mujoco_on_ode = dir_.Write("a.val", "/Simulation/MuJoCo/Integrator=Implicit\n");
  ProcessResult result = Run({"-env", kExample, "-val", mujoco_on_ode, "--duration", "0.1"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("/Simulation/MuJoCo/Integrator: applies to the MuJoCo engine only, and "
                                    "/Simulation/Engine is ODE"));
  const std::string ode_on_mujoco =
      dir_.Write("b.val", "/Simulation/Engine=MuJoCo\n/Simulation/ODE/QuickStepIterations=50\n");
  result = Run({"-env", kExample, "-val", ode_on_mujoco, "--duration", "0.1"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("/Simulation/ODE/QuickStepIterations: applies to the ODE engine only"));
}

// --engine puts the world on an engine over what value files say; the name is checked like any option.
TEST_F(OrcsSimTest, EngineOptionChoosesTheEngineOverValueFiles) {
  const std::string ode = dir_.Write("ode.val", "/Simulation/Engine=ODE\n");
  const ProcessResult result =
      Run({"-env", kExample, "-val", ode, "--engine", "mujoco", "--print-values", "/Simulation/Engine"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "/Simulation/Engine=MuJoCo\n");
  const ProcessResult unknown = Run({"-env", kExample, "--engine", "Bullet"});
  ExpectBadInput(unknown);
  EXPECT_THAT(unknown.err, HasSubstr("--engine: Bullet not in {ODE,MuJoCo}"));
}

// A world ODE runs but MuJoCo's compiler refuses (a dust grain's inertia, 4e-22 kg·m², is below MuJoCo's
// smallest): one line naming the object, exit 2, never MuJoCo's two-line report or a crash.
TEST_F(OrcsSimTest, AWorldMujocoCannotCompileIsOneLineNamingTheObject) {
  const std::string env = dir_.Write("dust.xml", R"xml(<?xml version="1.0"?>
<ORCS version="1.0">
  <Environment>
    <object type="sphere" name="Dust" position="(0, 0.5, 0)" dimension="(0.000001)" material="ABS"
            dynamic="true" mass="0.000000001"/>
  </Environment>
</ORCS>
)xml");
  ASSERT_EQ(Run({"-env", env, "--duration", "0.1"}).exit_code, 0);  // ODE takes it
  const ProcessResult result = Run({"-env", env, "--engine", "MuJoCo", "--duration", "0.1"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("MuJoCo cannot compile the world: 'Dust': inertia must have positive "
                                    "eigenvalues (line "));
}

TEST_F(OrcsSimTest, NonexistentEnvironment) {
  const std::string env = dir_.PathOf("nonexistent.xml");
  const ProcessResult result = Run({"-env", env});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(env + ": cannot read the file: no such file"));
}

TEST_F(OrcsSimTest, NonexistentValueFile) {
  const std::string val = dir_.PathOf("nonexistent.val");
  const ProcessResult result = Run({"-env", kExample, "-val", val});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(val + ": "));
  EXPECT_THAT(result.err, HasSubstr("cannot read"));
}

TEST_F(OrcsSimTest, LogWithoutOut) {
  const ProcessResult result = Run({"-env", kExample, "--log", ".*Position"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("--out"));
}

TEST_F(OrcsSimTest, LogMatchingNothing) {
  const ProcessResult result =
      Run({"-env", kExample, "--duration", "0.1", "--log", "/Sim/Nothing/.*", "--out", dir_.PathOf("s.csv")});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("'/Sim/Nothing/.*'"));
  EXPECT_THAT(result.err, HasSubstr("matches no"));
  EXPECT_FALSE(fs::exists(dir_.PathOf("s.csv")));
}

TEST_F(OrcsSimTest, UnwritableOutput) {
  const std::string out = dir_.PathOf("missing-dir/s.csv");
  const ProcessResult result = Run({"-env", kExample, "--duration", "0.1", "--log", ".*Position", "--out", out});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("missing-dir/s.csv"));
}

TEST_F(OrcsSimTest, UnknownOption) {
  const ProcessResult result = Run({"-env", kExample, "--speed", "2"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("--speed"));
}

TEST_F(OrcsSimTest, NegativeDuration) {
  const ProcessResult result = Run({"-env", kExample, "--duration", "-1"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("--duration"));
}

TEST_F(OrcsSimTest, DurationThatIsNotANumberOrTooLong) {
  for (const char* duration : {"nan", "1e30"}) {
    SCOPED_TRACE(duration);
    const ProcessResult result = Run({"--duration", duration});
    ExpectBadInput(result);
    EXPECT_THAT(result.err, HasSubstr("--duration"));
  }
}

// ---------------------------------------------------------------------------------------------------------
// -play AGENT RECORD

// Two pendulum rigs side by side: "Left" and "Right".
std::string TwoPendulums(const TempDir& dir) {
  return dir.Write("rigs.xml", R"x(<ORCS version="1.0"><Agent>
  <Pendulum name="Left" position="(-0.5,0.5,0)"/>
  <Pendulum name="Right" position="(0.5,0.5,0)"/>
</Agent></ORCS>)x");
}

TEST_F(OrcsSimTest, PlayDrivesOnlyTheNamedAgentBySimulatedTime) {
  const std::string record = dir_.Write("up.csv", "# layout: raw\n0,0,1\n500,60,1\n");
  const std::string quiet = dir_.Write("quiet.val", "/AngularMotor/IncludeNoise=F\n");  // exact angles
  const ProcessResult result = Run({"-env", TwoPendulums(dir_), "-val", quiet, "-play", "Right", record, "--duration",
                                    "2", "--log", ".*Motor/JointAngle", "--out", dir_.PathOf("out.csv")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  const Csv csv = ReadCsv(dir_.PathOf("out.csv"));
  const int left = csv.Column("/Sim/Left/Motor/JointAngle");
  const int right = csv.Column("/Sim/Right/Motor/JointAngle");
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  ASSERT_EQ(csv.rows.size(), 201u);
  // Before the 500 ms row the rig holds 0°; the row starts the move at the step that begins at 0.5 s.
  for (int row : {10, 49, 50}) EXPECT_NEAR(csv.rows[row][right], 0.0, 1e-3) << "row " << row;
  EXPECT_GT(csv.rows[51][right], 0.1);
  EXPECT_GT(csv.rows[60][right], 5.0);
  EXPECT_NEAR(csv.rows.back()[right], 60.0, 2.0);
  EXPECT_NEAR(csv.rows.back()[left], 0.0, 1e-3);
}

TEST_F(OrcsSimTest, PlayClampsOutOfRangeAnglesWithOneWarningNamingTheJoint) {
  const std::string record = dir_.Write("far.csv", "# layout: raw\n0,170,1\n100,175,1\n");
  const ProcessResult result = Run({"-env", TwoPendulums(dir_), "-play", "Left", record, "--duration", "0.2"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "orcs-sim: " + record +
                            ":2: warning: Motor/DesiredAngle 170 is outside -150…150; clamped here and wherever "
                            "else it is outside\n");
}

TEST_F(OrcsSimTest, PlayWithAnUnknownAgent) {
  const std::string record = dir_.Write("r.csv", "0,0,1\n");
  const ProcessResult result = Run({"-env", TwoPendulums(dir_), "-play", "Middle", record});
  ExpectBadInput(result);
  EXPECT_EQ(result.err, "orcs-sim: -play: unknown agent 'Middle' (agents: Left, Right)\n");
}

TEST_F(OrcsSimTest, PlayWithABadRecordNamesFileAndLine) {
  const struct {
    const char* contents;
    const char* error;
  } cases[] = {
      {"0,0,1\n10,0\n", ":2: expected 3 columns"},
      {"0,0,1\n10,zero,1\n", ":2: column 2 expected a finite number, found 'zero'"},
      {"0,0,1\n# comment\n20,0,1\n10,0,1\n", ":4: time goes backwards: 10 ms after 20 ms on line 3"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.contents);
    const std::string record = dir_.Write("bad.csv", c.contents);
    const ProcessResult result = Run({"-env", TwoPendulums(dir_), "-play", "Left", record});
    ExpectBadInput(result);
    EXPECT_THAT(result.err, HasSubstr("orcs-sim: " + record + c.error));
  }
}

TEST_F(OrcsSimTest, PlayGivesOneRecordPerAgentAndRecordsMatchTheAgent) {
  const std::string record = dir_.Write("r.csv", "# layout: raw\n0,0,1\n");
  ExpectBadInput(Run({"-env", TwoPendulums(dir_), "-play", "Left", record, "-play", "Left", record}));
  // A 1-motor record for the 21-motor A-Series: the row width is wrong.
  const ProcessResult result = Run({"-play", "Humanoid", record});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr(record + ":2: expected 43 columns"));
}

TEST_F(OrcsSimTest, PlayWithAMissingRecordOrArgument) {
  ExpectBadInput(Run({"-play", "Humanoid", dir_.PathOf("missing.csv")}));
  ExpectBadInput(Run({"-play", "Humanoid"}));
}

// --scenario: one job evaluated as a worker would, printed as one results.jsonl line.
constexpr const char* kHipScenario = R"({
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]},
  "randomisation": {"sets": 2, "default_motor_model": true},
  "genome": [20, 2, 0, 0, 20, 2, 3, 0]
})";

TEST_F(OrcsSimTest, ScenarioPrintsOneResultLineThatDependsOnSeedAndGenomeOnly) {
  const std::string scenario = dir_.Write("hips.json", kHipScenario);
  const ProcessResult first = Run({"--scenario", scenario, "--seed", "5"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const nlohmann::json line = nlohmann::json::parse(first.out);
  EXPECT_EQ(line["status"], "ok");
  EXPECT_EQ(line["seed"], 5);
  EXPECT_EQ(line["sets"].size(), 2u);
  EXPECT_GT(line["fitness"].get<double>(), 0.3);  // the head stays up
  // What a job computes, without its timings (wall clock).
  const auto computed = [](const ProcessResult& result) {
    const nlohmann::json parsed = nlohmann::json::parse(result.out);
    return parsed["fitness"].dump() + parsed["sets"].dump();
  };
  EXPECT_EQ(computed(Run({"--scenario", scenario, "--seed", "5"})), computed(first));
  EXPECT_NE(computed(Run({"--scenario", scenario, "--seed", "6"})), computed(first));
  const std::string genome = dir_.Write("g.json", "[0, 1, 0, 0, 0, 1, 0, 0]");
  EXPECT_NE(computed(Run({"--scenario", scenario, "--seed", "5", "--genome", "@" + genome})), computed(first));
}

// --engine with --scenario runs the job on that engine, and the result line says so.
TEST_F(OrcsSimTest, ScenarioRunsOnTheEngineTheOptionNames) {
  const std::string scenario = dir_.Write("hips.json", kHipScenario);
  const ProcessResult ode = Run({"--scenario", scenario, "--seed", "5"});
  const ProcessResult mujoco = Run({"--scenario", scenario, "--seed", "5", "--engine", "MuJoCo"});
  ASSERT_EQ(ode.exit_code, 0) << ode.err;
  ASSERT_EQ(mujoco.exit_code, 0) << mujoco.err;
  const nlohmann::json ode_line = nlohmann::json::parse(ode.out), mujoco_line = nlohmann::json::parse(mujoco.out);
  EXPECT_EQ(ode_line["engine"], "ODE");
  EXPECT_EQ(mujoco_line["engine"], "MuJoCo");
  EXPECT_NE(mujoco_line["fitness"], ode_line["fitness"]);  // another engine, other bits
  EXPECT_GT(mujoco_line["fitness"].get<double>(), 0.3);     // and the head stays up there too
}

// A job whose step MuJoCo warns about (gravity of 1e11 m/s² gives accelerations beyond MuJoCo's 1e10 limit: "bad
// number in qacc") is the job status "unstable_physics" with MuJoCo's words, exit 1: a recorded status, no crash.
TEST_F(OrcsSimTest, AMujocoWarningMakesTheJobUnstablePhysicsWithMujocosMessage) {
  nlohmann::json scenario = nlohmann::json::parse(kHipScenario);
  scenario["values"] = {{"/Simulation/Gravitation", 1e11}};
  scenario["randomisation"]["sets"] = 1;
  const std::string file = dir_.Write("heavy.json", scenario.dump());
  const ProcessResult result = Run({"--scenario", file, "--engine", "MuJoCo"});
  EXPECT_EQ(result.signal, 0);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  const nlohmann::json line = nlohmann::json::parse(result.out);
  EXPECT_EQ(line["status"], "unstable_physics");
  EXPECT_EQ(line["engine"], "MuJoCo");
  EXPECT_THAT(line["sets"][0]["message"].get<std::string>(),
              HasSubstr("physics engine error at t=0 s: MuJoCo: bad number in qacc"));
}

TEST_F(OrcsSimTest, ScenarioBadInputIsOneLine) {
  const std::string scenario = dir_.Write("hips.json", kHipScenario);
  ProcessResult result = Run({"--scenario", scenario, "--genome", "[1, 2]"});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("field 'genome' expected 8 numbers, found an array of 2"));
  result = Run({"--scenario", scenario, "-env", scenario});
  ExpectBadInput(result);
  EXPECT_THAT(result.err, HasSubstr("--scenario"));
  ExpectBadInput(Run({"--genome", "[1]"}));  // --genome needs --scenario
  ExpectBadInput(Run({"--scenario", dir_.PathOf("missing.json")}));
}

}  // namespace
}  // namespace orcs
