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
            "duration, agent, controller, fitness, randomisation, start_angles, schedules, log, genome, fault, evolution, record), found 'duratoin'");
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
              HasSubstr("field 'randomisation.sets' expected an integer ≥ 1"));
  EXPECT_THAT(InputErrorOf([&] { ParseScenario(with("environment", "x.xml"), "s.json"); }),
              HasSubstr("resolve the scenario file first"));
  nlohmann::json no_fitness = Minimal();
  no_fitness.erase("fitness");
  EXPECT_EQ(InputErrorOf([&] { ParseScenario(no_fitness, "s.json"); }),
            "s.json: field 'fitness' expected a value, found nothing (the field is missing)");
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
                                        0.5, 2.0, 0, 0, true});
    randomisation.parameters.push_back({"/Simulation/Gravitation", ParameterDistribution::Kind::kNormal, 9.0,
                                        10.0, 9.81, 5.0, false});
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
  randomisation.parameters.push_back({"/AngularMotor/Nope", ParameterDistribution::Kind::kUniform, 0, 1, 0, 0, false});
  EXPECT_EQ(InputErrorOf([&] { DrawParameterSets(randomisation, 1, simulation_.repository(), Motors(), "s.json"); }),
            "s.json: field 'randomisation.parameters[0].path' names an unknown repository path '/AngularMotor/Nope'");
  randomisation.parameters[0].path = "/Sim/Floor/Material";
  EXPECT_THAT(InputErrorOf([&] { DrawParameterSets(randomisation, 1, simulation_.repository(), Motors(), "s.json"); }),
              HasSubstr("expected the path of a number, found '/Sim/Floor/Material'"));
}

}  // namespace
}  // namespace orcs::scene
