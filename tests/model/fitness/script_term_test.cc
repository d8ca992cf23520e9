// Scripted fitness terms in whole jobs (model/fitness/script_term.h): the shipped distance and energy scripts give
// the built-ins' bits on every job of the shipped regression suite; stop() ends a set; a failing script ends its set
// with a script status and one line; a script that cannot compile is invalid input before any simulation.
#include "model/fitness/script_term.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/evaluation/evaluation.h"
#include "model/fitness/fitness_function.h"
#include "model/scene/scenario.h"
#include "tests/support/input_error_of.h"

namespace orcs::fitness {
namespace {

using evaluation::EvaluationOutcome;
using evaluation::EvaluationRequest;
using evaluation::EvaluationStatus;
using ::testing::AllOf;
using ::testing::HasSubstr;
using test_support::InputErrorOf;

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const std::filesystem::path kScripts = std::filesystem::path(ORCS_SOURCE_DIR) / "scenarios/examples/scripts";

nlohmann::json ScriptTermOf(const std::string& file, const std::string& name, double weight,
                            nlohmann::json params = nlohmann::json::object()) {
  return {{"type", "script"}, {"name", name}, {"weight", weight},
          {"script", {{"file", file}, {"text", ReadText(kScripts / file)}}}, {"params", std::move(params)}};
}

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// Every job of the shipped regression suite, with a distance and an energy term added: once built in, once as the
// shipped scripts. Each set's terms and fitness are the same bits.
TEST(ScriptTermTest, ScriptedDistanceAndEnergyGiveTheBuiltInsBitsOnTheRegressionSuite) {
  const std::filesystem::path folder = std::filesystem::path(ORCS_SOURCE_DIR) / "scenarios/regress";
  const nlohmann::json suite = nlohmann::json::parse(ReadText(folder / "suite.json"));
  int compared = 0;
  for (const nlohmann::json& entry : suite["cases"]) {
    SCOPED_TRACE(entry["name"].get<std::string>());
    const std::filesystem::path path = folder / entry["scenario"].get<std::string>();
    const nlohmann::json resolved = scene::ResolveScenarioFile(path.string());
    const bool pendulum = resolved.value("agent", "Humanoid") == "Pendulum";
    const std::string body = pendulum ? "Pole" : "Middle/UpperBody";
    nlohmann::json built_in = resolved, scripted = resolved;
    built_in["fitness"]["terms"].push_back({{"type", "distance"}, {"name", "moved"}, {"weight", 3.5}, {"body", body}, {"axis", "z"}});
    built_in["fitness"]["terms"].push_back({{"type", "energy"}, {"name", "work"}, {"weight", -0.25}});
    scripted["fitness"]["terms"].push_back(ScriptTermOf("distance.lua", "moved", 3.5, {{"body", body}, {"axis", "z"}}));
    scripted["fitness"]["terms"].push_back(ScriptTermOf("energy.lua", "work", -0.25));
    nlohmann::json genome = resolved.value("genome", nlohmann::json::array());
    if (entry.contains("genome")) {
      genome = nlohmann::json::parse(ReadText(folder / entry["genome"].get<std::string>().substr(1)));
    }
    EvaluationRequest a, b;
    a.scenario = scene::ParseScenario(built_in, path.string());
    b.scenario = scene::ParseScenario(scripted, path.string());
    a.genome = b.genome = genome;
    a.seed = b.seed = entry.value("seed", std::uint64_t{1});  // the suite's default seed
    const EvaluationOutcome want = evaluation::Evaluate(a);
    const EvaluationOutcome got = evaluation::Evaluate(b);
    ASSERT_EQ(want.status, EvaluationStatus::kOk) << want.message;
    ASSERT_EQ(got.status, EvaluationStatus::kOk) << got.message;
    ASSERT_EQ(got.sets.size(), want.sets.size());
    for (std::size_t k = 0; k < want.sets.size(); ++k) {
      ASSERT_EQ(got.sets[k].terms.size(), want.sets[k].terms.size());
      for (std::size_t t = 0; t < want.sets[k].terms.size(); ++t) {
        EXPECT_EQ(got.sets[k].terms[t].first, want.sets[k].terms[t].first);
        EXPECT_EQ(Bits(got.sets[k].terms[t].second), Bits(want.sets[k].terms[t].second))
            << want.sets[k].terms[t].first << ": " << got.sets[k].terms[t].second << " vs "
            << want.sets[k].terms[t].second;
      }
      EXPECT_EQ(Bits(got.sets[k].fitness), Bits(want.sets[k].fitness));
    }
    EXPECT_EQ(Bits(got.fitness), Bits(want.fitness));
    EXPECT_NE(want.sets[0].terms.back().second, 0.0);  // the motors did work: the comparison compares something
    ++compared;
  }
  EXPECT_EQ(compared, static_cast<int>(suite["cases"].size()));
}

// A pendulum swung by a keyframe record for `duration` s, with `terms` as its fitness.
EvaluationRequest PendulumJob(nlohmann::json terms, double duration = 1.0) {
  const std::string path = std::string(ORCS_SOURCE_DIR) + "/scenarios/examples/pendulum_keyframes.json";
  nlohmann::json resolved = scene::ResolveScenarioFile(path);
  resolved["fitness"] = {{"terms", std::move(terms)}};
  resolved["duration"] = duration;
  EvaluationRequest request;
  request.scenario = scene::ParseScenario(resolved, path);
  request.seed = 3;
  return request;
}

nlohmann::json InlineTerm(const std::string& name, const std::string& text, nlohmann::json limits = nullptr) {
  nlohmann::json term = {{"type", "script"}, {"name", name}, {"script", {{"file", name + ".lua"}, {"text", text}}}};
  if (!limits.is_null()) term["limits"] = std::move(limits);
  return term;
}

TEST(ScriptTermTest, StopEndsTheSetWhereTheScriptSays) {
  const EvaluationOutcome outcome = evaluation::Evaluate(PendulumJob(
      {InlineTerm("until_half", "function stop() return orcs.time() >= 0.5 end\nfunction finish() return orcs.time() end")},
      2.0));
  ASSERT_EQ(outcome.status, EvaluationStatus::kOk) << outcome.message;
  EXPECT_NEAR(outcome.sets[0].simulated_seconds, 0.5, 1e-9);
  EXPECT_NEAR(outcome.fitness, 0.5, 1e-9);
}

TEST(ScriptTermTest, AFailingScriptEndsItsSetWithAScriptStatusAndOneLine) {
  const EvaluationOutcome error = evaluation::Evaluate(PendulumJob(
      {InlineTerm("nosy", "function step(dt)\n  if orcs.time() > 0.2 then io.open('/etc/passwd') end\nend\n"
                          "function finish() return 0 end")}));
  EXPECT_EQ(error.status, EvaluationStatus::kScriptError);
  EXPECT_THAT(error.message, AllOf(HasSubstr("parameter set 0: script nosy.lua:2: io.open is not available"),
                                   HasSubstr("(in step)")));
  EXPECT_EQ(error.message.find('\n'), std::string::npos);
  EXPECT_NEAR(error.sets[0].simulated_seconds, 0.2, 0.011);  // it ran until the script failed

  const EvaluationOutcome limit = evaluation::Evaluate(PendulumJob(
      {InlineTerm("spin", "function finish()\n  while true do end\nend", {{"instructions", 100000}})}));
  EXPECT_EQ(limit.status, EvaluationStatus::kScriptLimit);
  EXPECT_THAT(limit.message, HasSubstr("script 'spin.lua' line 2: instruction budget of 100000 per parameter set "
                                       "exceeded in finish"));

  const EvaluationOutcome nan = evaluation::Evaluate(PendulumJob({InlineTerm("nan", "function finish() return 0/0 end")}));
  EXPECT_EQ(nan.status, EvaluationStatus::kScriptError);
  EXPECT_THAT(nan.message, HasSubstr("finish() expected to return a finite number"));
}

TEST(ScriptTermTest, AScriptThatCannotRunIsInvalidInputBeforeAnySimulation) {
  const EvaluationRequest typo = PendulumJob({InlineTerm("typo", "function finish()\n  return 1 +\nend")});
  EXPECT_THAT(InputErrorOf([&] { evaluation::CheckRequest(typo); }), HasSubstr("script typo.lua:3:"));
  const EvaluationOutcome outcome = evaluation::Evaluate(typo);
  EXPECT_EQ(outcome.status, EvaluationStatus::kInvalidInput);
  EXPECT_TRUE(outcome.sets.empty());  // nothing was simulated
  EXPECT_THAT(InputErrorOf([&] { CheckFitness({{"terms", {InlineTerm("typo", "x = = 1")}}}, "s.json"); }),
              HasSubstr("script typo.lua:1:"));
  EXPECT_THAT(InputErrorOf([&] { evaluation::CheckRequest(PendulumJob({InlineTerm("empty", "x = 1")})); }),
              HasSubstr("empty.lua: a fitness script defines function finish()"));
  EXPECT_THAT(InputErrorOf([&] { evaluation::CheckRequest(PendulumJob({InlineTerm("top", "while true do end\nfunction finish() return 1 end", {{"instructions", 10000}})})); }),
              HasSubstr("instruction budget of 10000"));
}

// The API reads the simulation: a body's height, a motor's angle, time, and the set's own random stream.
TEST(ScriptTermTest, TheOrcsTableReadsTheRunningSimulation) {
  const std::string text =
      "local pole = orcs.body('Pole')\nlocal sum, angle_sum, steps = 0, 0, 0\n"
      "function step(dt)\n  local x, y, z = orcs.position(pole)\n  sum = sum + y\n"
      "  angle_sum = angle_sum + orcs.angle(orcs.motors()[1])\n  steps = steps + 1\nend\n"
      "function finish() return sum / steps + 0 * orcs.random() end\n";
  const EvaluationOutcome outcome = evaluation::Evaluate(PendulumJob({InlineTerm("height", text)}));
  ASSERT_EQ(outcome.status, EvaluationStatus::kOk) << outcome.message;
  EXPECT_GT(outcome.fitness, 0.1);  // the pole hangs from a pivot 0.5 m up
  EXPECT_LT(outcome.fitness, 0.5);
  const EvaluationOutcome bad = evaluation::Evaluate(PendulumJob({InlineTerm("ghost", "function finish() return select(2, orcs.position('Ghost')) end")}));
  EXPECT_EQ(bad.status, EvaluationStatus::kScriptError);
  EXPECT_THAT(bad.message, HasSubstr("orcs.position: agent 'Pendulum' has no body 'Ghost'"));
}

// The shipped script examples run as jobs (shortened): each term reports a value in its range.
TEST(ScriptTermTest, TheShippedScriptExamplesRun) {
  const auto run = [](const std::string& example) {
    const std::string path = std::string(ORCS_SOURCE_DIR) + "/scenarios/examples/" + example;
    nlohmann::json resolved = scene::ResolveScenarioFile(path);
    resolved["duration"] = 1.0;
    resolved["randomisation"]["sets"] = 2;
    EvaluationRequest request;
    request.scenario = scene::ParseScenario(resolved, path);
    request.genome = resolved["genome"];
    request.seed = 1;
    const EvaluationOutcome outcome = evaluation::Evaluate(request);
    EXPECT_EQ(outcome.status, EvaluationStatus::kOk) << outcome.message;
    return outcome;
  };
  const EvaluationOutcome level = run("head_level.json");
  ASSERT_FALSE(level.sets.empty());
  const double tilt = level.sets[0].terms.at(0).second;  // head_tilt, degrees: the head of a robot rocking 6°
  EXPECT_GT(tilt, 0.0);
  EXPECT_LT(tilt, 10.0);
  const EvaluationOutcome target = run("target_walk.json");
  ASSERT_FALSE(target.sets.empty());
  const double to_target = target.sets[0].terms.at(0).second;  // −(distance to a point 0.3 m ahead) − speed
  EXPECT_LT(to_target, -0.25);
  EXPECT_GT(to_target, -0.5);
  EXPECT_EQ(run("cpg_walk.json").sets.size(), 2u);
}

}  // namespace
}  // namespace orcs::fitness
