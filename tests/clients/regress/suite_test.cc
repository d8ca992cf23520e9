// Regression suites: what a suite file may say, and that every mistake is one error naming the suite and field.
#include "clients/regress/suite.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::regress {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::HasSubstr;

// Hip oscillators: a genome of 8 numbers, the scenario's own given.
constexpr const char* kScenario = R"({
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]},
  "genome": [10, 1, 0, 0, 10, 1, 3, 0]
})";

class SuiteTest : public ::testing::Test {
 protected:
  SuiteTest() {
    dir_.Write("scenarios/hips.json", kScenario);
    dir_.Write("suites/genome.json", "[1, 2, 0, 0, 1, 2, 0, 0]");
  }
  // A suite in suites/, so that its scenarios are found through "../scenarios/".
  std::string Suite(const std::string& text) { return dir_.Write("suites/s.json", text); }
  std::string ErrorOf(const std::string& text) {
    const std::string path = Suite(text);
    return InputErrorOf([&] { ReadSuite(path); });
  }
  TempDir dir_;
};

TEST_F(SuiteTest, ReadsCasesWithTheirScenariosGenomesSeedsValuesAndTolerances) {
  const regress::Suite suite = ReadSuite(Suite(R"({
    "name": "hips-suite",
    "tolerance": {"absolute": 0.01, "relative": 0.001},
    "cases": [
      {"name": "plain", "scenario": "../scenarios/hips.json"},
      {"name": "inline.genome_2", "scenario": "../scenarios/hips.json", "genome": [5, 1, 0, 0, 5, 1, 0, 0],
       "seed": 7, "values": {"/AngularMotor/FMaxFactor": 0.5, "/AngularMotor/IncludeNoise": true,
                             "/Sim/Floor/Material": "Carpet"},
       "tolerance": {"relative": 0.1}, "comment": "comments are allowed"},
      {"name": "file-genome", "scenario": "../scenarios/hips.json", "genome": "@genome.json",
       "tolerance": {"absolute": 0}}
    ]})"));
  EXPECT_EQ(suite.name, "hips-suite");
  ASSERT_EQ(suite.cases.size(), 3u);
  const SuiteCase& plain = suite.cases[0];
  EXPECT_EQ(plain.name, "plain");
  EXPECT_EQ(plain.field, "cases[0]");
  EXPECT_EQ(plain.seed, 1u) << "the default seed";
  EXPECT_EQ(plain.genome.value, nlohmann::json({10, 1, 0, 0, 10, 1, 3, 0})) << "the scenario's genome";
  EXPECT_EQ(plain.scenario.scenario.duration, 0.1);
  EXPECT_EQ(plain.tolerance.absolute, 0.01);
  EXPECT_EQ(plain.tolerance.relative, 0.001);

  const SuiteCase& inline_genome = suite.cases[1];
  EXPECT_EQ(inline_genome.genome.value, nlohmann::json({5, 1, 0, 0, 5, 1, 0, 0}));
  EXPECT_THAT(inline_genome.genome.source, HasSubstr("field 'cases[1].genome'"));
  EXPECT_EQ(inline_genome.seed, 7u);
  const std::vector<std::pair<std::string, std::string>> values = {
      {"/AngularMotor/FMaxFactor", "0.5"}, {"/AngularMotor/IncludeNoise", "T"}, {"/Sim/Floor/Material", "Carpet"}};
  EXPECT_EQ(inline_genome.values, values);
  EXPECT_EQ(inline_genome.tolerance.absolute, 0.01) << "a member the case leaves out is the suite's";
  EXPECT_EQ(inline_genome.tolerance.relative, 0.1);

  const SuiteCase& file_genome = suite.cases[2];
  EXPECT_EQ(file_genome.genome.value, nlohmann::json({1, 2, 0, 0, 1, 2, 0, 0})) << "@FILE beside the suite";
  EXPECT_EQ(file_genome.tolerance.absolute, 0.0);
  EXPECT_EQ(file_genome.tolerance.relative, 0.001);
}

TEST_F(SuiteTest, TheNameDefaultsToTheFileStemAndTheToleranceToExact) {
  const regress::Suite suite = ReadSuite(Suite(R"({"cases": [{"name": "a", "scenario": "../scenarios/hips.json"}]})"));
  EXPECT_EQ(suite.name, "s");
  EXPECT_EQ(suite.cases[0].tolerance.absolute, 0.0);
  EXPECT_EQ(suite.cases[0].tolerance.relative, 0.0);
}

// Issue 47, item 5: the suite's name is the default output folder runs/<name>, so it is a label as a scenario's is.
TEST_F(SuiteTest, ASuiteNameThatIsAPathIsRefusedNamingTheField) {
  const std::string cases = R"("cases": [{"name": "a", "scenario": "../scenarios/hips.json"}])";
  EXPECT_THAT(ErrorOf(R"({"name": "../../escaped", )" + cases + "}"),
              HasSubstr("s.json: field 'name' expected a label of 1 to 128 bytes of UTF-8 without '/', '\\' or control "
                        "characters, not '.' or '..', found the string \"../../escaped\" (it contains '/')"));
  EXPECT_THAT(ErrorOf(R"({"name": "..", )" + cases + "}"), HasSubstr("(it is '..')"));
  EXPECT_EQ(ReadSuite(Suite(R"({"name": "hips suite", )" + cases + "}")).name, "hips suite");
}

TEST(ToleranceTest, AllowsTheLooserOfAbsoluteAndRelative) {
  const Tolerance tolerance{0.5, 0.1};
  EXPECT_EQ(tolerance.Allowed(2.0), 0.5);
  EXPECT_EQ(tolerance.Allowed(-20.0), 2.0) << "relative to |baseline|";
  EXPECT_EQ(Tolerance{}.Allowed(3.0), 0.0);
}

TEST_F(SuiteTest, BadSuitesAreOneErrorNamingTheSuiteAndTheField) {
  const std::string hips = R"("scenario": "../scenarios/hips.json")";
  struct Case {
    std::string suite;
    std::string message;
  };
  const std::vector<Case> cases = {
      {R"({"nmae": "x", "cases": []})",
       "s.json: field 'nmae' expected no such field (allowed: name, tolerance, cases)"},
      {R"({"name": "x"})", "s.json: field 'cases' expected a value, found nothing"},
      {R"({"cases": []})", "s.json: field 'cases' expected at least one case, found an array of 0"},
      {R"({"cases": [{"name": "a", "scenaro": "x.json"}]})", "s.json: field 'cases[0].scenaro' expected no such field"},
      {R"({"cases": [{"scenario": "x.json"}]})", "s.json: field 'cases[0].name' expected a value, found nothing"},
      {R"({"cases": [{"name": "a b", )" + hips + "}]}", "s.json: field 'cases[0].name' expected a name of letters"},
      {R"({"cases": [{"name": "a", )" + hips + R"(}, {"name": "b", )" + hips + R"(}, {"name": "a", )" + hips + "}]}",
       "s.json: field 'cases[2].name' expected a name no other case has, found \"a\", the name of cases[0] too"},
      {R"({"cases": [{"name": "a", "scenario": "../scenarios/missing.json"}]})",
       "s.json: field 'cases[0].scenario' of case 'a': "},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "genome": 3}]})",
       "s.json: field 'cases[0].genome' expected a genome (an array, a network object or \"@FILE\"), found the number "
       "3"},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "genome": "@nothing.json"}]})", "nothing.json: cannot read"},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "seed": -1}]})", "s.json: field 'cases[0].seed' expected a seed"},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "values": {"AngularMotor/FMaxFactor": 1}}]})",
       "s.json: field 'cases[0].values.AngularMotor/FMaxFactor' expected a repository path starting with '/'"},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "values": {"/AngularMotor/FMaxFactor": [1]}}]})",
       "s.json: field 'cases[0].values./AngularMotor/FMaxFactor' expected a number, a boolean or a string"},
      {R"({"tolerance": {"relative": -0.1}, "cases": [{"name": "a", )" + hips + "}]}",
       "s.json: field 'tolerance.relative' expected a number ≥ 0, found the number -0.1"},
      {R"({"cases": [{"name": "a", )" + hips + R"(, "tolerance": {"abs": 1}}]})",
       "s.json: field 'cases[0].tolerance.abs' expected no such field (allowed: absolute, relative)"},
  };
  for (const Case& c : cases) EXPECT_THAT(ErrorOf(c.suite), HasSubstr(c.message)) << c.suite;
}

TEST_F(SuiteTest, ACaseWhoseScenarioDoesNotLoadNamesTheCaseAndTheScenarioField) {
  dir_.Write("scenarios/bad.json",
             R"({"duration": -1, "controller": {"type": "keyframes"}, "fitness": {"terms": []}})");
  const std::string error = ErrorOf(R"({"cases": [{"name": "bad-one", "scenario": "../scenarios/bad.json"}]})");
  EXPECT_THAT(error, HasSubstr("s.json: field 'cases[0].scenario' of case 'bad-one': "));
  EXPECT_THAT(error, HasSubstr("bad.json: field 'duration'"));
  EXPECT_EQ(error.find('\n'), std::string::npos) << "one line";
}

TEST(DefaultBaselinePathTest, IsBesideTheSuite) {
  EXPECT_EQ(DefaultBaselinePath("scenarios/regress/suite.json"), "scenarios/regress/suite.baseline.json");
  EXPECT_EQ(DefaultBaselinePath("my-suite"), "my-suite.baseline.json");
}

}  // namespace
}  // namespace orcs::regress
