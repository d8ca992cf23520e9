// The "evolution" section of a scenario and the command line's overrides: what they set, and that every mistake is
// an InputError naming the scenario file and the field (or the option) before anything is submitted. Also that
// MinimumPopulation() agrees with pagmo2's own checks.
#include "clients/evolve/evolution_settings.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <string>

#include "clients/evolve/evolution.h"
#include "clients/runtime/batch_input.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::evolve {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr Algorithm kAlgorithms[] = {Algorithm::kCmaes, Algorithm::kXnes, Algorithm::kSga, Algorithm::kDe,
                                     Algorithm::kPsoGen};

// Two hip oscillators: a flat genome of 8 genes. `more` is added to the object (", \"evolution\": {...}").
std::string HipsScenario(const std::string& more) {
  return std::string(R"({
  "name": "hips",
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]})") +
         more + "\n}";
}

class EvolutionSettingsTest : public ::testing::Test {
 protected:
  runtime::ScenarioInput Load(const std::string& more) {
    return runtime::LoadScenario(dir_.Write("hips.json", HipsScenario(more)));
  }
  EvolutionSettings Read(const std::string& more, const EvolutionOverrides& overrides = {}) {
    return ReadEvolutionSettings(Load(more), overrides);
  }
  std::string ErrorOf(const std::string& more, const EvolutionOverrides& overrides = {}) {
    const runtime::ScenarioInput input = Load(more);
    return InputErrorOf([&] { ReadEvolutionSettings(input, overrides); });
  }
  TempDir dir_;
};

TEST_F(EvolutionSettingsTest, ReadsTheSectionAndFillsInTheDefaults) {
  const EvolutionSettings defaults = Read(R"(, "evolution": {"bounds": [-3, 4]})");
  EXPECT_EQ(defaults.algorithm, Algorithm::kCmaes);
  EXPECT_EQ(defaults.population, 16);
  EXPECT_EQ(defaults.generations, 30);
  EXPECT_EQ(defaults.seed, 1u);
  EXPECT_EQ(defaults.sigma, 0.3);
  EXPECT_EQ(defaults.validate, 8);
  EXPECT_TRUE(defaults.start.empty()) << "no \"genome\" in the scenario";

  const EvolutionSettings full = Read(R"(, "genome": [1, 2, 3, 4, 5, 6, 7, 8],
    "evolution": {"bounds": [0, 10], "algorithm": "de", "population": 6, "generations": 3, "seed": 9,
                  "sigma": 0.5, "validate": 2})");
  EXPECT_EQ(full.algorithm, Algorithm::kDe);
  EXPECT_EQ(full.population, 6);
  EXPECT_EQ(full.generations, 3);
  EXPECT_EQ(full.seed, 9u);
  EXPECT_EQ(full.sigma, 0.5);
  EXPECT_EQ(full.validate, 2);
  EXPECT_EQ(full.start, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST_F(EvolutionSettingsTest, OneLowHighPairAppliesToEveryGene) {
  const EvolutionSettings settings = Read(R"(, "evolution": {"bounds": [-3, 4.5]})");
  ASSERT_EQ(settings.bounds.size(), 8u);
  for (const GeneBounds& b : settings.bounds) {
    EXPECT_EQ(b.low, -3.0);
    EXPECT_EQ(b.high, 4.5);
  }
}

TEST_F(EvolutionSettingsTest, OnePairPerGeneIsKeptInGenomeOrder) {
  const EvolutionSettings settings =
      Read(R"(, "evolution": {"bounds": [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 6], [6, 7], [-8, 7]]})");
  ASSERT_EQ(settings.bounds.size(), 8u);
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(settings.bounds[i].low, i);
    EXPECT_EQ(settings.bounds[i].high, i + 1);
  }
  EXPECT_EQ(settings.bounds[7].low, -8.0);
  EXPECT_EQ(settings.bounds[7].high, 7.0);
}

TEST_F(EvolutionSettingsTest, OverridesReplaceTheFilesValuesAndUnsetOnesKeepThem) {
  const std::string section = R"(, "evolution": {"bounds": [0, 1], "algorithm": "de", "population": 6,
                                                  "generations": 3, "seed": 9, "validate": 2})";
  EvolutionOverrides overrides;
  overrides.algorithm = "sga";
  overrides.population = 4;
  overrides.generations = 0;
  overrides.seed = 0;
  overrides.validate = 0;
  const EvolutionSettings replaced = Read(section, overrides);
  EXPECT_EQ(replaced.algorithm, Algorithm::kSga);
  EXPECT_EQ(replaced.population, 4);
  EXPECT_EQ(replaced.generations, 0);
  EXPECT_EQ(replaced.seed, 0u);
  EXPECT_EQ(replaced.validate, 0);

  const EvolutionSettings kept = Read(section, EvolutionOverrides{});
  EXPECT_EQ(kept.algorithm, Algorithm::kDe);
  EXPECT_EQ(kept.population, 6);
  EXPECT_EQ(kept.generations, 3);
  EXPECT_EQ(kept.seed, 9u);
  EXPECT_EQ(kept.validate, 2);
}

TEST_F(EvolutionSettingsTest, NoEvolutionSectionNamesTheFile) {
  EXPECT_THAT(ErrorOf(""), AllOf(HasSubstr("hips.json"), HasSubstr("no field 'evolution'"), HasSubstr("bounds")));
}

TEST_F(EvolutionSettingsTest, NoBoundsNamesTheField) {
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"algorithm": "de"})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution'"), HasSubstr("no \"bounds\"")));
}

TEST_F(EvolutionSettingsTest, BoundsOfTheWrongLengthNameTheGeneCount) {
  EXPECT_THAT(
      ErrorOf(R"(, "evolution": {"bounds": [[0, 1], [0, 1]]})"),
      AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.bounds'"), HasSubstr("(8)"), HasSubstr("2 ranges")));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1, 2]})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.bounds'"), HasSubstr("low < high")));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": []})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.bounds'")));
}

TEST_F(EvolutionSettingsTest, LowNotBelowHighNamesTheRange) {
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [1, 1]})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.bounds'"), HasSubstr("low < high")));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [[0, 1], [0, 1], [0, 1], [2, 1], [0, 1], [0, 1], [0, 1], [0, 1]]})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.bounds[3]'"), HasSubstr("low < high")));
}

TEST_F(EvolutionSettingsTest, AnUnknownAlgorithmNamesTheFieldOrTheOption) {
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "algorithm": "cma-es"})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'evolution.algorithm'"), HasSubstr("\"cmaes\""),
                    HasSubstr("cma-es")));
  EvolutionOverrides overrides;
  overrides.algorithm = "nonsense";
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1]})", overrides),
              AllOf(HasSubstr("--algorithm 'nonsense'"), HasSubstr("\"pso_gen\"")));
}

TEST_F(EvolutionSettingsTest, AnUnknownFieldInTheSectionIsNamed) {
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "populaton": 8})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("'populaton'")));
}

TEST_F(EvolutionSettingsTest, APopulationBelowTheAlgorithmsMinimumNamesBoth) {
  for (const Algorithm algorithm : kAlgorithms) {
    const std::string name = AlgorithmName(algorithm);
    const int minimum = MinimumPopulation(algorithm);
    SCOPED_TRACE(name);
    const std::string section = R"(, "evolution": {"bounds": [0, 1], "algorithm": ")" + name + R"(", "population": )";
    EXPECT_THAT(
        ErrorOf(section + std::to_string(minimum - 1) + "}"),
        AllOf(HasSubstr("hips.json"), HasSubstr("population " + std::to_string(minimum - 1)),
              HasSubstr("evolution.population"), HasSubstr(name + " needs at least " + std::to_string(minimum))));
    EXPECT_EQ(Read(section + std::to_string(minimum) + "}").population, minimum);

    // The same through --population and through --algorithm.
    EvolutionOverrides population;
    population.population = minimum - 1;
    EXPECT_THAT(ErrorOf(section + "50}", population),
                AllOf(HasSubstr("--population"), HasSubstr(name + " needs at least " + std::to_string(minimum))));
  }
  EvolutionOverrides algorithm;
  algorithm.algorithm = "cmaes";
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "algorithm": "sga", "population": 3})", algorithm),
              HasSubstr("cmaes needs at least 5"));
}

TEST_F(EvolutionSettingsTest, AStartGenomeOutsideItsBoundsNamesTheGene) {
  EXPECT_THAT(ErrorOf(R"(, "genome": [0, 0, 0, 0, 0, 1.5, 0, 0], "evolution": {"bounds": [-1, 1]})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'genome[5]'"), HasSubstr("outside its bounds"),
                    HasSubstr("evolution.bounds")));
  EXPECT_THAT(ErrorOf(R"(, "genome": [0, 0, 0], "evolution": {"bounds": [-1, 1]})"),
              AllOf(HasSubstr("hips.json"), HasSubstr("field 'genome'"), HasSubstr("8 genes")));
  // Its ends are inside.
  EXPECT_EQ(Read(R"(, "genome": [-1, 1, 0, 0, 0, 0, 0, 0], "evolution": {"bounds": [-1, 1]})").start[0], -1.0);
}

TEST_F(EvolutionSettingsTest, AControllerWithoutGenesCannotBeEvolved) {
  const std::string scenario = R"({
  "name": "pendulum-keyframes",
  "environment": ")" + std::string(ORCS_SOURCE_DIR) +
                               R"(/scenarios/environments/pendulum.xml",
  "agent": "Pendulum",
  "duration": 0.1,
  "controller": {"type": "keyframes", "record": ")" +
                               std::string(ORCS_SOURCE_DIR) +
                               R"(/scenarios/examples/pendulum_quarter.csv"},
  "fitness": {"terms": [{"type": "tracking_error", "record": ")" +
                               std::string(ORCS_SOURCE_DIR) +
                               R"(/scenarios/examples/pendulum_quarter.csv", "weight": -1}]},
  "evolution": {"bounds": [0, 1]}
})";
  const runtime::ScenarioInput input = runtime::LoadScenario(dir_.Write("keyframes.json", scenario));
  EXPECT_THAT(InputErrorOf([&] { ReadEvolutionSettings(input, {}); }),
              AllOf(HasSubstr("keyframes.json"), HasSubstr("field 'controller'"), HasSubstr("no free genes")));
}

TEST_F(EvolutionSettingsTest, SigmaGenerationsAndValidateAreChecked) {
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "sigma": 0})"), HasSubstr("field 'evolution.sigma'"));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "sigma": 1.5})"), HasSubstr("field 'evolution.sigma'"));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "generations": -1})"),
              HasSubstr("field 'evolution.generations'"));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "validate": -2})"), HasSubstr("field 'evolution.validate'"));
  EXPECT_THAT(ErrorOf(R"(, "evolution": {"bounds": [0, 1], "seed": -2})"), HasSubstr("field 'evolution.seed'"));
}

// ---- MinimumPopulation against pagmo2 itself ----

// The unit box in 3 dimensions; any smooth objective.
struct UnitSphere {
  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    return {(x[0] - 0.3) * (x[0] - 0.3) + (x[1] - 0.6) * (x[1] - 0.6) + x[2] * x[2]};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return {{0, 0, 0}, {1, 1, 1}}; }
};

// Whether pagmo runs `algorithm` (as orcs-batch configures it) for three generations on `size` individuals;
// pagmo's message in `error` when it refuses.
bool PagmoRuns(Algorithm algorithm, unsigned size, std::string* error = nullptr) {
  EvolutionSettings settings;
  settings.algorithm = algorithm;
  pagmo::algorithm pagmo_algorithm = MakeAlgorithm(settings);
  pagmo::population population(pagmo::problem{UnitSphere{}}, size, 3u);
  try {
    for (int generation = 0; generation < 3; ++generation) population = pagmo_algorithm.evolve(population);
  } catch (const std::invalid_argument& refused) {
    if (error != nullptr) *error = refused.what();
    return false;
  }
  return true;
}

TEST(MinimumPopulationTest, AgreesWithPagmo) {
  for (const Algorithm algorithm : kAlgorithms) {
    SCOPED_TRACE(AlgorithmName(algorithm));
    const int minimum = MinimumPopulation(algorithm);
    EXPECT_TRUE(PagmoRuns(algorithm, static_cast<unsigned>(minimum)));
    if (algorithm == Algorithm::kPsoGen) continue;  // a swarm of 1 crashes pagmo 2.18's pso_gen: not tried
    std::string error;
    if (algorithm == Algorithm::kXnes) {
      // pagmo 2.18's xNES says it "needs at least 5 individuals" but only refuses fewer than 4; orcs keeps to the
      // documented 5 (evolution_settings.cc). If pagmo starts refusing 4, MinimumPopulation is exact again.
      EXPECT_FALSE(PagmoRuns(algorithm, 3u, &error));
      EXPECT_THAT(error, HasSubstr("at least 5"));
      continue;
    }
    EXPECT_FALSE(PagmoRuns(algorithm, static_cast<unsigned>(minimum - 1), &error));
    EXPECT_THAT(error, HasSubstr("at least " + std::to_string(minimum)));
  }
}

TEST(MinimumPopulationTest, AlgorithmNamesAreTheDocumentedOnes) {
  EXPECT_EQ(AlgorithmName(Algorithm::kCmaes), "cmaes");
  EXPECT_EQ(AlgorithmName(Algorithm::kXnes), "xnes");
  EXPECT_EQ(AlgorithmName(Algorithm::kSga), "sga");
  EXPECT_EQ(AlgorithmName(Algorithm::kDe), "de");
  EXPECT_EQ(AlgorithmName(Algorithm::kPsoGen), "pso_gen");
}

}  // namespace
}  // namespace orcs::evolve
