#include "model/scene/scenario.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "model/scene/parameter_sets.h"
#include "model/scene/simulation.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::scene {
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

nlohmann::json Minimal() {
  return nlohmann::json::parse(R"({"controller": {"type": "oscillator", "joints": []},
                                   "fitness": {"terms": [{"type": "energy"}]}})");
}

TEST(ScenarioTest, MinimalScenarioTakesTheDefaults) {
  const Scenario scenario = ParseScenario(Minimal(), "s.json");
  EXPECT_EQ(scenario.name, "s");
  EXPECT_EQ(scenario.environment_xml, "");
  EXPECT_EQ(scenario.duration, 10.0);
  EXPECT_EQ(scenario.agent, "Humanoid");
  EXPECT_EQ(scenario.randomisation.sets, 1);
  EXPECT_EQ(scenario.aggregate, Aggregate::kMean);
}

TEST(ScenarioTest, ADefaultGenomeIsKeptAsGiven) {
  nlohmann::json scenario = Minimal();
  EXPECT_TRUE(ParseScenario(scenario, "s.json").genome.is_null());
  scenario["genome"] = {1.5, -2};
  EXPECT_EQ(ParseScenario(scenario, "s.json").genome, nlohmann::json({1.5, -2}));
}

TEST(ScenarioTest, AFaultIsReadForTheSandboxAndCheckedLikeEveryField) {
  nlohmann::json scenario = Minimal();
  EXPECT_EQ(ParseScenario(scenario, "s.json").fault.kind, FaultInjection::Kind::kNone);
  scenario["fault"] = {{"kind", "segfault"}, {"at_step", 40}};
  const FaultInjection segfault = ParseScenario(scenario, "s.json").fault;
  EXPECT_EQ(segfault.kind, FaultInjection::Kind::kSegfault);
  EXPECT_EQ(segfault.at_step, 40u);
  scenario["fault"] = {{"kind", "abort"}};
  EXPECT_EQ(ParseScenario(scenario, "s.json").fault.kind, FaultInjection::Kind::kAbort);
  EXPECT_EQ(ParseScenario(scenario, "s.json").fault.at_step, 0u);
  scenario["fault"] = {{"kind", "hang"}, {"at_step", 1}};
  EXPECT_EQ(ParseScenario(scenario, "s.json").fault.kind, FaultInjection::Kind::kHang);
  scenario["fault"] = {{"kind", "spin"}, {"at_step", 2}};
  EXPECT_EQ(ParseScenario(scenario, "s.json").fault.kind, FaultInjection::Kind::kSpin);

  scenario["fault"] = {{"kind", "explode"}};
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(scenario, "s.json"); }),
            "s.json: field 'fault.kind' expected \"segfault\", \"abort\", \"hang\" or \"spin\", found the string "
            "\"explode\"");
  scenario["fault"] = {{"kind", "abort"}, {"at_step", -3}};
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(scenario, "s.json"); }),
              HasSubstr("field 'fault.at_step' expected a step index ≥ 0"));
  scenario["fault"] = {{"kind", "abort"}, {"step", 3}};
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(scenario, "s.json"); }), HasSubstr("field 'fault.step' expected no such field"));
}

TEST(ScenarioTest, BadInputNamesFileAndField) {
  auto with = [](const char* key, nlohmann::json value) {
    nlohmann::json scenario = Minimal();
    scenario[key] = std::move(value);
    return scenario;
  };
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("duratoin", 3), "s.json"); }),
            "s.json: field 'duratoin' expected no such field (allowed: name, environment, value_files, values, "
            "duration, agent, controller, fitness, randomisation, start_angles, schedules, log, genome, fault, evolution, record, "
            "motor_model), found 'duratoin'");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("motor_model", {{"plugin", "pd"}}), "s.json"); }),
            "s.json: field 'motor_model.plugin' expected \"<plug-in>/<component>\", e.g. \"example/pd\", found the "
            "string \"pd\"");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("motor_model", {{"plugin", "example/pd"}, {"params", 3}}), "s.json"); }),
            "s.json: field 'motor_model.params' expected an object of the plug-in's parameters, found the number 3");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("record", "yes"), "s.json"); }),
            "s.json: field 'record' expected true or false, found the string \"yes\"");
  EXPECT_TRUE(ParseScenario(with("record", true), "s.json").record);
  EXPECT_FALSE(ParseScenario(Minimal(), "s.json").record);
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("evolution", {1, 2}), "s.json"); }),
            "s.json: field 'evolution' expected an object (orcs-batch evolve's settings), found an array of 2");
  EXPECT_EQ(ParseScenario(with("evolution", {{"bounds", {-1, 1}}}), "s.json").evolution["bounds"][1], 1);
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("genome", 5), "s.json"); }),
            "s.json: field 'genome' expected an array of numbers or a network object, found the number 5");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(with("duration", "long"), "s.json"); }),
            "s.json: field 'duration' expected seconds > 0, found the string \"long\"");
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(with("duration", -1), "s.json"); }),
              HasSubstr("field 'duration' expected seconds, 0 < duration"));
  EXPECT_EQ(InputErrorOf([&] {
              ParseScenario(with("randomisation", {{"parameters", {{{"path", "/A"}, {"uniform", {2, 1}}}}}}), "s.json");
            }),
            "s.json: field 'randomisation.parameters[0].uniform' expected low ≤ high, found [2, 1]");
  EXPECT_THAT(InputErrorOf([&] {
                ParseScenario(with("randomisation",
                                   {{"parameters",
                                     {{{"path", "/A"}, {"normal", {{"mean", 0}, {"deviation", 1}, {"min", 3}, {"max", 1}}}}}}}),
                              "s.json");
              }),
              HasSubstr("field 'randomisation.parameters[0].normal.min' expected min ≤ max (1)"));
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(with("randomisation", {{"sets", 0}}), "s.json"); }),
              HasSubstr("field 'randomisation.sets' expected an integer from 1 to 10000"));
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(with("environment", "x.xml"), "s.json"); }),
              HasSubstr("resolve the scenario file first"));
  nlohmann::json no_fitness = Minimal();
  no_fitness.erase("fitness");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(no_fitness, "s.json"); }),
            "s.json: field 'fitness' expected a value, found nothing (the field is missing)");
}

// Issue 47, item 5: "sets": 1e9 ended in std::bad_alloc at 3.1 GB, naming nothing. Every count that costs memory in
// proportion to a number in the file has a documented bound, refused naming its field before anything is allocated.
TEST(ScenarioTest, CountsThatCostMemoryAreBoundedNamingTheirField) {
  auto randomised = [](nlohmann::json randomisation) {
    nlohmann::json scenario = Minimal();
    scenario["randomisation"] = std::move(randomisation);
    return scenario;
  };
  for (const nlohmann::json& sets : {nlohmann::json(1000000000), nlohmann::json(10001), nlohmann::json(1e10),
                                    nlohmann::json(-1), nlohmann::json(2.5)}) {
    SCOPED_TRACE(sets.dump());
    EXPECT_EQ(InputErrorOf([&] { ParseScenario(randomised({{"sets", sets}}), "s.json"); }),
              "s.json: field 'randomisation.sets' expected an integer from 1 to 10000, found the number " + sets.dump());
  }
  EXPECT_EQ(ParseScenario(randomised({{"sets", 10000}}), "s.json").randomisation.sets, 10000);

  // The values a job draws: sets × parameters, at most 100,000 (default_motor_model adds 7 parameters).
  EXPECT_EQ(ParseScenario(randomised({{"sets", 10000}, {"default_motor_model", true}}), "s.json").randomisation.sets,
            10000) << "70,000 drawn values";
  nlohmann::json parameters = nlohmann::json::array();
  for (int i = 0; i < 11; ++i) parameters.push_back({{"path", "/A" + std::to_string(i)}, {"uniform", {0, 1}}});
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(randomised({{"sets", 10000}, {"parameters", parameters}}), "s.json"); }),
            "s.json: field 'randomisation.sets' expected at most 100000 drawn values per job (sets × parameters), "
            "found 10000 sets × 11 parameters");
  nlohmann::json many = nlohmann::json::array();
  for (int i = 0; i < 993; ++i) many.push_back({{"path", "/A"}, {"uniform", {0, 1}}});
  EXPECT_EQ(ParseScenario(randomised({{"default_motor_model", true}, {"parameters", many}}), "s.json")
                .randomisation.parameters.size(),
            1000u);
  many.push_back({{"path", "/A"}, {"uniform", {0, 1}}});
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(randomised({{"default_motor_model", true}, {"parameters", many}}), "s.json"); }),
            "s.json: field 'randomisation.parameters' expected at most 1000 parameters with default_motor_model's 7, "
            "found an array of 994");

  nlohmann::json scenario = Minimal();
  scenario["log"] = nlohmann::json::array();
  for (int i = 0; i < 1000; ++i) scenario["log"].push_back("/Simulation/Time");
  EXPECT_EQ(ParseScenario(scenario, "s.json").log.size(), 1000u);
  scenario["log"].push_back("/Simulation/Time");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(scenario, "s.json"); }),
            "s.json: field 'log' expected at most 1000 regular expressions, found an array of 1001");
}

// Issue 47, item 5: a name of "../../escaped" or "/tmp/x" wrote the results outside runs/ (the default output folder
// is runs/<name>). A name is a label: 1…128 bytes of UTF-8, no '/', '\\' or control character, not "." or "..".
TEST(ScenarioTest, ANameIsALabelThatCannotLeaveTheRunsFolder) {
  auto named = [](const std::string& name) {
    nlohmann::json scenario = Minimal();
    scenario["name"] = name;
    return scenario;
  };
  // What the shipped scenarios, suites and tests use keeps working.
  for (const std::string& name : std::vector<std::string>{"rock-oscillator", "swing-robustness", "a b", "inline.genome_2", ".hidden", "x",
                                 "caf\xc3\xa9 \xe2\x82\xac", std::string(128, 'n')}) {
    EXPECT_EQ(ParseScenario(named(name), "s.json").name, name);
  }
  const std::string rule =
      "s.json: field 'name' expected a label of 1 to 128 bytes of UTF-8 without '/', '\\' or control characters, "
      "not '.' or '..', found ";
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named("../../escaped"), "s.json"); }),
            rule + "the string \"../../escaped\" (it contains '/')");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named("/tmp/absolute"), "s.json"); }),
            rule + "the string \"/tmp/absolute\" (it contains '/')");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named(".."), "s.json"); }), rule + "the string \"..\" (it is '..')");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named("."), "s.json"); }), rule + "the string \".\" (it is '.')");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named(""), "s.json"); }), rule + "the string \"\" (it is empty)");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named("a\\b"), "s.json"); }),
            rule + "the string \"a\\b\" (it contains '\\')");
  // A NUL no longer cuts the message, and a newline does not make it two lines: both are shown escaped.
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named(std::string("a\0b", 3)), "s.json"); }),
            rule + "the string \"a\\x00b\" (it contains a control character)");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named("a\nb"), "s.json"); }),
            rule + "the string \"a\\nb\" (it contains a control character)");
  // 100,000 characters: refused, and the message quotes 80 of them.
  const std::string error = InputErrorOf([&] { ParseScenario(named(std::string(100000, 'n')), "s.json"); });
  EXPECT_EQ(error, rule + "the string \"" + std::string(80, 'n') + "...\" (it has 100000 bytes)");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(named(std::string(129, 'n')), "s.json"); }),
            rule + "the string \"" + std::string(80, 'n') + "...\" (it has 129 bytes)");

  // Without a name, the file's stem is made a name that keeps the rule.
  EXPECT_EQ(ParseScenario(Minimal(), "dir/walk.json").name, "walk");
  EXPECT_EQ(ParseScenario(Minimal(), "job j-1 scenario").name, "job j-1 scenario");
  EXPECT_EQ(ParseScenario(Minimal(), "dir/...json").name, "scenario") << "the stem '..'";
  EXPECT_EQ(ParseScenario(Minimal(), "dir/a\\b\tc.json").name, "a_b_c");
  EXPECT_EQ(ParseScenario(Minimal(), "dir/" + std::string(200, 'n') + ".json").name, std::string(128, 'n'));
}

TEST(ScenarioTest, ResolveInlinesEnvironmentValueFilesAndRecords) {
  test_support::TempDir dir;
  dir.Write("env/world.xml", R"(<ORCS version="1.0"><Agent><Pendulum/></Agent></ORCS>)");
  dir.Write("motor.val", "/AngularMotor/PID/Proportional=25\n");
  dir.Write("moves/r.csv", "# layout: raw\n0,10,1\n");
  const std::string path = dir.Write("s.json", R"({"environment": "env/world.xml", "value_files": ["motor.val"],
      "agent": "Pendulum", "controller": {"type": "keyframes", "record": "moves/r.csv"},
      "fitness": {"terms": [{"type": "tracking_error", "record": "moves/r.csv"}]}})");
  const nlohmann::json resolved = ResolveScenarioFile(path);
  EXPECT_EQ(resolved["environment"]["file"], "env/world.xml");
  EXPECT_THAT(resolved["environment"]["xml"].get<std::string>(), HasSubstr("<Pendulum/>"));
  EXPECT_EQ(resolved["controller"]["record"]["text"], "# layout: raw\n0,10,1\n");
  EXPECT_EQ(resolved["fitness"]["terms"][0]["record"]["file"], "moves/r.csv");
  const Scenario scenario = ParseScenario(resolved, path);
  ASSERT_EQ(scenario.values.size(), 1u);
  EXPECT_EQ(scenario.values[0].path, "/AngularMotor/PID/Proportional");
  EXPECT_EQ(scenario.values[0].value, "25");
}

TEST(ScenarioTest, ResolveNamesAMissingFileAndTheFieldReferencingIt) {
  test_support::TempDir dir;
  const std::string path = dir.Write("s.json", R"({"environment": "nowhere.xml"})");
  EXPECT_THAT(InputErrorOf([&] { ResolveScenarioFile(path); }),
              HasSubstr("field 'environment' expected a readable file"));
}

TEST(ScenarioTest, AggregatesMeanMinMaxAndQuantile) {
  const std::vector<double> values{4, 1, 3, 2};
  EXPECT_EQ(AggregateFitness(values, Aggregate::kMean, 0), 2.5);
  EXPECT_EQ(AggregateFitness(values, Aggregate::kMin, 0), 1.0);
  EXPECT_EQ(AggregateFitness(values, Aggregate::kMax, 0), 4.0);
  EXPECT_EQ(AggregateFitness(values, Aggregate::kQuantile, 0.5), 2.5);    // between 2 and 3
  EXPECT_EQ(AggregateFitness(values, Aggregate::kQuantile, 0.25), 1.75);  // 1 + 0.75·(2 − 1)
}

class ParameterSetsTest : public ::testing::Test {
 protected:
  ParameterSetsTest() {
    EnvironmentDescription environment;
    environment.agents.push_back(AgentDescription{});
    simulation_.LoadEnvironment(environment);
    simulation_.Build();
  }
  Randomisation Varied() {
    Randomisation randomisation;
    randomisation.sets = 50;
    randomisation.parameters.push_back({"/AngularMotor/PID/Proportional", ParameterDistribution::Kind::kUniform,
                                        0.5, 2.0, 0, 0, true, ""});
    randomisation.parameters.push_back({"/Simulation/Gravitation", ParameterDistribution::Kind::kNormal, 9.0,
                                        10.0, 9.81, 5.0, false, ""});
    randomisation.parameter_files = {{"a.val", {}}, {"b.val", {}}, {"c.val", {}}};
    randomisation.start_pose.position = {0.1, 0.05, 0.1};
    return randomisation;
  }
  const std::vector<aseries::MorphologyMotor>& Motors() const { return simulation_.model().morphology(0).motors; }
  Simulation simulation_;
};

TEST_F(ParameterSetsTest, DrawsFromTheSeedAloneWithinTheDistributions) {
  const std::vector<ParameterSet> a = DrawParameterSets(Varied(), 7, simulation_.repository(), Motors(), "s.json");
  const std::vector<ParameterSet> b = DrawParameterSets(Varied(), 7, simulation_.repository(), Motors(), "s.json");
  const std::vector<ParameterSet> c = DrawParameterSets(Varied(), 8, simulation_.repository(), Motors(), "s.json");
  ASSERT_EQ(a.size(), 50u);
  bool clamped_low = false, clamped_high = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].values, b[k].values);  // bit for bit
    EXPECT_GE(a[k].values[0].second, 0.5 * 20.0);  // relative to Kp's nominal 20
    EXPECT_LE(a[k].values[0].second, 2.0 * 20.0);
    EXPECT_GE(a[k].values[1].second, 9.0);  // the normal's clamp
    EXPECT_LE(a[k].values[1].second, 10.0);
    clamped_low |= a[k].values[1].second == 9.0;
    clamped_high |= a[k].values[1].second == 10.0;
    EXPECT_GE(a[k].position_offset.y(), 0.0);  // never into the floor
    EXPECT_LE(std::abs(a[k].position_offset.x()), 0.1);
    EXPECT_GE(a[k].parameter_file, 0);
    EXPECT_LT(a[k].parameter_file, 3);
  }
  EXPECT_TRUE(clamped_low && clamped_high);  // σ = 5 around 9.81 hits both clamps among 50 draws
  EXPECT_NE(a[0].values, c[0].values);
}

TEST_F(ParameterSetsTest, FilesInSequenceCycle) {
  Randomisation randomisation = Varied();
  randomisation.files_in_sequence = true;
  const std::vector<ParameterSet> sets = DrawParameterSets(randomisation, 1, simulation_.repository(), Motors(), "s.json");
  for (int k = 0; k < 6; ++k) EXPECT_EQ(sets[k].parameter_file, k % 3);
}

TEST_F(ParameterSetsTest, UnknownOrNonNumericPathIsNamed) {
  Randomisation randomisation;
  randomisation.parameters.push_back({"/AngularMotor/Nope", ParameterDistribution::Kind::kUniform, 0, 1, 0, 0, false, ""});
  EXPECT_EQ(InputErrorOf([&] { DrawParameterSets(randomisation, 1, simulation_.repository(), Motors(), "s.json"); }),
            "s.json: field 'randomisation.parameters[0].path' names an unknown repository path '/AngularMotor/Nope'");
  randomisation.parameters[0].path = "/Sim/Floor/Material";
  EXPECT_THAT(InputErrorOf([&] { DrawParameterSets(randomisation, 1, simulation_.repository(), Motors(), "s.json"); }),
              HasSubstr("expected the path of a number, found '/Sim/Floor/Material'"));
}

}  // namespace
}  // namespace orcs::scene
