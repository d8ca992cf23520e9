// Robots from files (issue 48, docs/formats.md "Robot files"): the shipped long-shinned A-Series loads from its
// file, stands on both engines, travels inline; bad robot files are one line naming the file and the field; a
// robot written back reads as the same robot.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "model/aseries/aseries_morphology.h"
#include "model/core/error.h"
#include "model/core/text_file.h"
#include "model/scene/environment_reader.h"
#include "model/scene/simulation.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::scene {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const std::string kLongShins = ORCS_SOURCE_DIR "/scenarios/environments/long_shins.xml";

double HeadHeight(const Simulation& simulation) {
  return simulation.repository().Get("/Sim/Humanoid/Middle/Head/Position").as_vector3().y();
}

class LongShinsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(LongShinsTest, TheLongShinnedRobotLoadsFromItsFileAndStandsForFiveSeconds) {
  const EnvironmentDescription environment = EnvironmentReader::ReadFile(kLongShins);
  ASSERT_EQ(environment.agents.size(), 1u);
  ASSERT_NE(environment.agents[0].morphology, nullptr);
  EXPECT_THAT(environment.agents[0].morphology_source, HasSubstr("aseries_long_shins.json"));
  Simulation simulation;
  simulation.LoadEnvironment(environment);
  simulation.repository().Set("/Simulation/Engine", GetParam());
  simulation.Build();
  const double start = HeadHeight(simulation);
  EXPECT_NEAR(start, 0.4037 + 0.03, 1e-9) << "3 cm taller than the built-in A-Series";
  EXPECT_DOUBLE_EQ(simulation.repository().Get("/Sim/Humanoid/Right/Tibia/Height").as_double(), 0.079);
  for (int step = 0; step < 500; ++step) ASSERT_EQ(simulation.Step(), SimulationStatus::kOk) << simulation.message();
  EXPECT_NEAR(HeadHeight(simulation), start, 0.01) << "still standing after 5 s";
}

INSTANTIATE_TEST_SUITE_P(Engines, LongShinsTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const auto& engine) { return engine.param; });

TEST(RobotFileTest, AJobCarriesTheRobotInlineAndNeedsNoFile) {
  const std::string inlined = EnvironmentReader::InlineRobotFiles(ReadTextFile(kLongShins), kLongShins);
  EXPECT_THAT(inlined, HasSubstr("<Morphology source="));
  EXPECT_THAT(inlined, Not(HasSubstr("file=")));
  const EnvironmentDescription environment = EnvironmentReader::ReadString(inlined, "job");
  ASSERT_NE(environment.agents[0].morphology, nullptr);
  EXPECT_DOUBLE_EQ(environment.agents[0].morphology->bodies[2].size.y(), 0.079);  // Right/Tibia
  // XML without a file of its own cannot resolve a robot file's name.
  EXPECT_THAT(test_support::InputErrorOf([&] { EnvironmentReader::ReadString(ReadTextFile(kLongShins), "job"); }),
              HasSubstr("job:5: <ASeries> 'Humanoid': attribute 'file' names a robot file relative to the environment's file"));
}

TEST(RobotFileTest, BadRobotFilesAreOneLineNamingTheFileAndTheField) {
  test_support::TempDir dir;
  const std::string robot = ReadTextFile(ORCS_SOURCE_DIR "/scenarios/robots/aseries_long_shins.json");
  const auto environment_with = [&](const std::string& json) {
    dir.Write("robot.json", json);
    return dir.Write("env.xml", "<?xml version=\"1.0\"?>\n<ORCS version=\"1.0\">\n  <Agent>\n"
                                "    <ASeries name=\"Humanoid\" file=\"robot.json\"/>\n  </Agent>\n</ORCS>\n");
  };
  std::string massless = robot;
  massless.replace(massless.find("\"mass\": 0.13391"), 15, "\"mass\": -1");
  const std::string negative = test_support::InputErrorOf([&] { EnvironmentReader::ReadFile(environment_with(massless)); });
  EXPECT_THAT(negative, HasSubstr(dir.PathOf("robot.json") + ": field 'bodies[1].mass'"));
  EXPECT_EQ(negative.find('\n'), std::string::npos);
  const std::string broken = test_support::InputErrorOf([&] { EnvironmentReader::ReadFile(environment_with("{\"format\": ")); });
  EXPECT_THAT(broken, HasSubstr(dir.PathOf("robot.json")));
  const std::string missing = dir.Write("missing.xml", "<?xml version=\"1.0\"?>\n<ORCS version=\"1.0\">\n  <Agent>\n"
                                                       "    <ASeries file=\"nowhere.json\"/>\n  </Agent>\n</ORCS>\n");
  EXPECT_THAT(test_support::InputErrorOf([&] { EnvironmentReader::ReadFile(missing); }),
              HasSubstr(missing + ":4: attribute 'file' expected a readable robot file"));
}

TEST(RobotFileTest, ARobotWrittenBackReadsAsTheSameRobot) {
  const aseries::ASeriesMorphology& original = aseries::DefaultASeriesMorphology();
  const std::string written = aseries::WriteASeriesMorphology(original, {"a comment"});
  const aseries::ASeriesMorphology again = aseries::ParseASeriesMorphology(written, "written.json");
  EXPECT_EQ(aseries::WriteASeriesMorphology(again, {"a comment"}), written);
  ASSERT_EQ(again.bodies.size(), original.bodies.size());
  for (std::size_t b = 0; b < original.bodies.size(); ++b) {
    EXPECT_EQ(again.bodies[b].mass, original.bodies[b].mass);
    EXPECT_EQ(again.bodies[b].centre, original.bodies[b].centre);
  }
  EXPECT_EQ(again.motors.size(), original.motors.size());
  EXPECT_EQ(again.contact_exclusions.size(), original.contact_exclusions.size());
}

}  // namespace
}  // namespace orcs::scene
