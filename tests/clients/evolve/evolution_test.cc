// Evolution without a broker: analytic evaluators (fitness = −Σ(g_i − c_i)² in the genes' own units) stand in for
// the batches of jobs. The central claim of model/identify/batch_problem.h is checked for every algorithm: the
// two-pass rehearsal evaluates each generation as one batch and still runs, bit for bit, the search plain pagmo runs
// with direct evaluations. Also: failed jobs, the champion, the history, resuming from SaveState(), the gene mapping.
#include "clients/evolve/evolution.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <pagmo/problem.hpp>
#include <sstream>
#include <utility>
#include <set>
#include <vector>

#include "tests/support/input_error_of.h"

namespace orcs::evolve {
namespace {

using test_support::InputErrorOf;
using ::testing::AllOf;
using ::testing::HasSubstr;
using Genome = std::vector<double>;

const Genome kCentre = {1.0, 7.0, -0.5};  // where the analytic fitness peaks, in the genes' units

// −Σ(g_i − c_i)²: smooth, best (0) at kCentre.
double Sphere(const Genome& genome) {
  double sum = 0.0;
  for (std::size_t i = 0; i < genome.size(); ++i) sum += (genome[i] - kCentre[i]) * (genome[i] - kCentre[i]);
  return -sum;
}

Evaluation SphereOk(const Genome& genome) { return {Sphere(genome), true}; }

EvolutionSettings SettingsFor(Algorithm algorithm) {
  EvolutionSettings settings;
  settings.algorithm = algorithm;
  settings.population = 8;
  settings.seed = 5;
  settings.sigma = 0.3;
  settings.bounds = {{-2.0, 3.0}, {0.0, 10.0}, {-1.0, 1.0}};
  settings.start = {0.0, 5.0, 0.25};
  return settings;
}

// What an evaluator was asked and answered, one entry per call (= per batch).
struct BatchLog {
  std::vector<std::vector<Genome>> genomes;          ///< the genomes of each call
  std::vector<std::vector<Evaluation>> evaluations;  ///< the answers of each call
  std::vector<std::uint64_t> seeds;                  ///< the jobs' seed of each call
};

// An evaluator scoring each genome with `score` and logging every call into `log`.
GenomeEvaluator Logging(BatchLog& log, std::function<Evaluation(const Genome&)> score) {
  return [&log, score = std::move(score)](const std::vector<Genome>& genomes, std::uint64_t seed) {
    std::vector<Evaluation> evaluations;
    for (const Genome& genome : genomes) evaluations.push_back(score(genome));
    log.genomes.push_back(genomes);
    log.evaluations.push_back(evaluations);
    log.seeds.push_back(seed);
    return evaluations;
  };
}

// The same search problem as Evolution's, evaluated directly, one vector at a time, as plain pagmo does.
struct DirectProblem {
  const Evolution* evolution = nullptr;                      ///< for its gene mapping (GenomeOf)
  std::shared_ptr<std::vector<pagmo::vector_double>> asked;  ///< every vector evaluated, in order (when set)

  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    if (asked) asked->push_back(x);
    return {-Sphere(evolution->GenomeOf(x))};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    const std::size_t genes = evolution->settings().bounds.size();
    return {pagmo::vector_double(genes, 0.0), pagmo::vector_double(genes, 1.0)};
  }
};

// Doubles as their bit patterns: == is then "the same bits" (−0 ≠ +0, NaN = the same NaN).
std::vector<std::uint64_t> Bits(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits;
  for (double v : values) bits.push_back(std::bit_cast<std::uint64_t>(v));
  return bits;
}
std::vector<std::vector<std::uint64_t>> Bits(const std::vector<std::vector<double>>& rows) {
  std::vector<std::vector<std::uint64_t>> bits;
  for (const std::vector<double>& row : rows) bits.push_back(Bits(row));
  return bits;
}
std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

void ExpectSamePopulation(const pagmo::population& expected, const pagmo::population& actual) {
  EXPECT_EQ(Bits(actual.get_x()), Bits(expected.get_x()));
  EXPECT_EQ(Bits(actual.get_f()), Bits(expected.get_f()));
  EXPECT_EQ(actual.get_ID(), expected.get_ID());
}

void ExpectSameHistoryButSeconds(const std::vector<GenerationRecord>& expected,
                                 const std::vector<GenerationRecord>& actual) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t g = 0; g < expected.size(); ++g) {
    SCOPED_TRACE("generation " + std::to_string(g));
    EXPECT_EQ(actual[g].generation, expected[g].generation);
    EXPECT_EQ(actual[g].evaluations, expected[g].evaluations);
    EXPECT_EQ(actual[g].failed, expected[g].failed);
    EXPECT_EQ(Bits(actual[g].best), Bits(expected[g].best));
    EXPECT_EQ(Bits(actual[g].mean), Bits(expected[g].mean));
    EXPECT_EQ(Bits(actual[g].median), Bits(expected[g].median));
    EXPECT_EQ(Bits(actual[g].worst), Bits(expected[g].worst));
    EXPECT_EQ(Bits(actual[g].best_so_far), Bits(expected[g].best_so_far));
  }
}

void ExpectSameChampion(const Champion& expected, const Champion& actual) {
  EXPECT_EQ(Bits(actual.genome), Bits(expected.genome));
  EXPECT_EQ(Bits(actual.fitness), Bits(expected.fitness));
  EXPECT_EQ(actual.generation, expected.generation);
}

// ---- every algorithm ----

class EveryAlgorithmTest : public ::testing::TestWithParam<Algorithm> {};

TEST_P(EveryAlgorithmTest, SearchesBitForBitAsPlainPagmoWithDirectEvaluation) {
  BatchLog log;
  Evolution evolution(SettingsFor(GetParam()), Logging(log, SphereOk));
  evolution.Initialise();
  const std::vector<pagmo::vector_double> initial = evolution.population().get_x();

  // Plain pagmo: the same initial individuals, evaluated directly, and the same algorithm (same seed).
  pagmo::population plain(pagmo::problem{DirectProblem{&evolution, nullptr}}, 0u, evolution.population().get_seed());
  for (const pagmo::vector_double& x : evolution.population().get_x()) plain.push_back(x);
  ExpectSamePopulation(plain, evolution.population());
  pagmo::algorithm algorithm = MakeAlgorithm(evolution.settings());

  for (int generation = 1; generation <= 4; ++generation) {
    SCOPED_TRACE("generation " + std::to_string(generation));
    evolution.Step();
    plain = algorithm.evolve(plain);
    ExpectSamePopulation(plain, evolution.population());
  }
  // The search moved (a population that never changes would match trivially).
  EXPECT_NE(Bits(evolution.population().get_x()), Bits(initial));
}

// Each generation is one evaluator call holding exactly the genomes plain pagmo evaluates in that generation, in the
// order it asks for them, each once, and no vector is evaluated outside its batch. CMA-ES, xNES, DE and pso_gen ask
// for 8 different vectors per generation; SGA asks for 8 too, but its offspring repeat one another when crossover and
// mutation leave them unchanged: the batch evaluates each genome once (the jobs are deterministic).
TEST_P(EveryAlgorithmTest, EvaluatesEachGenerationAsOneBatchWithoutCacheMisses) {
  BatchLog log;
  Evolution evolution(SettingsFor(GetParam()), Logging(log, SphereOk));
  evolution.Initialise();
  EXPECT_EQ(log.genomes.size(), 1u);
  EXPECT_EQ(log.genomes[0].size(), 8u);
  EXPECT_EQ(log.genomes[0][0], evolution.settings().start) << "generation 0 starts from the scenario's genome";
  EXPECT_EQ(evolution.history()[0].evaluations, 8u);

  const auto asked = std::make_shared<std::vector<pagmo::vector_double>>();
  pagmo::population plain(pagmo::problem{DirectProblem{&evolution, asked}}, 0u, evolution.population().get_seed());
  for (const pagmo::vector_double& x : evolution.population().get_x()) plain.push_back(x);
  pagmo::algorithm algorithm = MakeAlgorithm(evolution.settings());
  std::size_t repeats = 0;
  for (int generation = 1; generation <= 4; ++generation) {
    SCOPED_TRACE("generation " + std::to_string(generation));
    asked->clear();
    plain = algorithm.evolve(plain);
    evolution.Step();
    EXPECT_EQ(evolution.generation(), generation);
    ASSERT_EQ(log.genomes.size(), static_cast<std::size_t>(generation + 1)) << "one batch per generation";
    EXPECT_EQ(asked->size(), 8u);
    std::vector<Genome> distinct;
    for (const pagmo::vector_double& x : *asked) {
      const Genome genome = evolution.GenomeOf(x);
      if (std::find(distinct.begin(), distinct.end(), genome) == distinct.end()) distinct.push_back(genome);
    }
    repeats += asked->size() - distinct.size();
    EXPECT_EQ(Bits(log.genomes.back()), Bits(distinct));
    EXPECT_EQ(evolution.history().back().evaluations, log.genomes.back().size());
  }
  EXPECT_EQ(evolution.cache_misses(), 0u);
  if (GetParam() == Algorithm::kSga) {
    EXPECT_GT(repeats, 0u) << "SGA repeats offspring (this seed); the batches held each once";
  } else {
    EXPECT_EQ(repeats, 0u) << "the whole population in each batch";
  }
}

TEST_P(EveryAlgorithmTest, ChampionIsTheBestGenomeEvaluatedAndBestSoFarNeverDrops) {
  BatchLog log;
  Evolution evolution(SettingsFor(GetParam()), Logging(log, SphereOk));
  evolution.Initialise();
  for (int generation = 1; generation <= 4; ++generation) evolution.Step();

  double best = -INFINITY;
  Genome best_genome;
  int best_generation = -1;
  for (std::size_t g = 0; g < log.genomes.size(); ++g) {
    for (std::size_t i = 0; i < log.genomes[g].size(); ++i) {
      if (log.evaluations[g][i].fitness > best) {
        best = log.evaluations[g][i].fitness;
        best_genome = log.genomes[g][i];
        best_generation = static_cast<int>(g);
      }
    }
    EXPECT_EQ(Bits(evolution.history()[g].best_so_far), Bits(best)) << "generation " << g;
    if (g > 0) {
      EXPECT_GE(evolution.history()[g].best_so_far, evolution.history()[g - 1].best_so_far);
    }
  }
  EXPECT_EQ(Bits(evolution.champion().genome), Bits(best_genome));
  EXPECT_EQ(Bits(evolution.champion().fitness), Bits(best));
  EXPECT_EQ(evolution.champion().generation, best_generation);
}

// ---- failed jobs ----

// Genomes whose first gene is above 0.5 "fail" (the optimum, gene 0 = 1, among them); a failed job's fitness is
// huge garbage, which must be ignored.
Evaluation FailAboveHalf(const Genome& genome) {
  if (genome[0] > 0.5) return {1e9, false};
  return SphereOk(genome);
}

TEST(EvolutionTest, FailedJobsAreCountedAndNeverBecomeChampion) {
  BatchLog log;
  Evolution evolution(SettingsFor(Algorithm::kCmaes), Logging(log, FailAboveHalf));
  evolution.Initialise();
  for (int generation = 1; generation <= 5; ++generation) evolution.Step();

  std::size_t failed_total = 0;
  double best_ok = -INFINITY;
  for (std::size_t g = 0; g < log.evaluations.size(); ++g) {
    SCOPED_TRACE("generation " + std::to_string(g));
    std::vector<double> ok;
    std::size_t failed = 0;
    for (const Evaluation& e : log.evaluations[g]) {
      if (e.ok) {
        ok.push_back(e.fitness);
      } else {
        ++failed;
      }
    }
    failed_total += failed;
    const GenerationRecord& record = evolution.history()[g];
    EXPECT_EQ(record.failed, failed);
    EXPECT_EQ(record.evaluations, log.evaluations[g].size());
    ASSERT_FALSE(ok.empty());
    EXPECT_EQ(record.best, *std::max_element(ok.begin(), ok.end()));
    EXPECT_EQ(record.worst, *std::min_element(ok.begin(), ok.end()));
    EXPECT_LE(record.median, record.best);
    EXPECT_GE(record.median, record.worst);
    best_ok = std::max(best_ok, record.best);
  }
  EXPECT_GT(failed_total, 0u) << "the test must actually produce failures";
  EXPECT_LE(evolution.champion().genome[0], 0.5) << "a failed genome became champion";
  EXPECT_EQ(evolution.champion().fitness, best_ok);
  EXPECT_EQ(evolution.history().back().best_so_far, best_ok);
}

// Without fresh sets every batch has the run's seed (the same K parameter sets throughout); with them every
// generation has its own seed, GenerationSeed, none of them the run's seed or a validation seed S+1…S+8. The champion
// keeps the seed it was scored with, so that its replay can be exact.
TEST(EvolutionTest, FreshSetsGiveEveryGenerationItsOwnSeedAndTheChampionKeepsItsOwn) {
  for (const bool fresh : {false, true}) {
    SCOPED_TRACE(fresh ? "fresh sets" : "the same sets");
    EvolutionSettings settings = SettingsFor(Algorithm::kCmaes);
    settings.fresh_sets = fresh;
    BatchLog log;
    Evolution evolution(settings, Logging(log, SphereOk));
    evolution.Initialise();
    for (int generation = 1; generation <= 4; ++generation) evolution.Step();
    ASSERT_EQ(log.seeds.size(), 5u);
    std::set<std::uint64_t> distinct(log.seeds.begin(), log.seeds.end());
    for (std::size_t g = 0; g < log.seeds.size(); ++g) {
      EXPECT_EQ(log.seeds[g], GenerationSeed(settings, static_cast<int>(g)));
      if (fresh) {
        EXPECT_FALSE(log.seeds[g] >= settings.seed && log.seeds[g] <= settings.seed + 8) << "generation " << g;
      } else {
        EXPECT_EQ(log.seeds[g], settings.seed);
      }
    }
    EXPECT_EQ(distinct.size(), fresh ? 5u : 1u);
    const Champion& champion = evolution.champion();
    EXPECT_EQ(champion.seed, log.seeds.at(static_cast<std::size_t>(champion.generation)));
  }
  // The generation seeds are the run seed's: another run seed, other seeds; the same, the same.
  EvolutionSettings a = SettingsFor(Algorithm::kCmaes);
  a.fresh_sets = true;
  EvolutionSettings b = a;
  b.seed = a.seed + 1;
  EXPECT_NE(GenerationSeed(a, 3), GenerationSeed(b, 3));
  EXPECT_EQ(GenerationSeed(a, 3), GenerationSeed(a, 3));
}

// A generation in which every job fails (a time limit too short, physics unstable everywhere): NaN statistics, no
// champion, and the search goes on: the next generation evaluates genomes again. (pagmo's CMA-ES and xNES stop
// before sampling when the population's objectives all lie within ftol: every failed job has the same objective.)
TEST_P(EveryAlgorithmTest, AGenerationWithoutOkJobsHasNaNStatisticsAndTheSearchGoesOn) {
  BatchLog log;
  // Everything fails in the first batch; from then on everything runs.
  Evolution evolution(SettingsFor(GetParam()), Logging(log, [&log](const Genome& genome) {
                        return log.genomes.empty() ? Evaluation{5.0, false} : SphereOk(genome);
                      }));
  evolution.Initialise();
  const GenerationRecord first = evolution.history().at(0);
  EXPECT_EQ(first.evaluations, 8u);
  EXPECT_EQ(first.failed, 8u);
  EXPECT_TRUE(std::isnan(first.best));
  EXPECT_TRUE(std::isnan(first.mean));
  EXPECT_TRUE(std::isnan(first.median));
  EXPECT_TRUE(std::isnan(first.worst));
  EXPECT_TRUE(std::isnan(first.best_so_far));
  EXPECT_TRUE(evolution.champion().genome.empty());
  EXPECT_EQ(evolution.champion().generation, -1);

  for (int generation = 1; generation <= 3; ++generation) evolution.Step();
  for (int g = 1; g <= 3; ++g) {
    SCOPED_TRACE("generation " + std::to_string(g));
    const GenerationRecord& record = evolution.history().at(g);
    EXPECT_GT(record.evaluations, 0u);
    EXPECT_EQ(record.failed, 0u);
    EXPECT_FALSE(std::isnan(record.best));
  }
  EXPECT_GT(evolution.champion().generation, 0);
  EXPECT_EQ(evolution.champion().fitness, evolution.history().back().best_so_far);
}

INSTANTIATE_TEST_SUITE_P(Algorithms, EveryAlgorithmTest,
                         ::testing::Values(Algorithm::kCmaes, Algorithm::kXnes, Algorithm::kSga, Algorithm::kDe,
                                           Algorithm::kPsoGen),
                         [](const ::testing::TestParamInfo<Algorithm>& param) { return AlgorithmName(param.param); });

TEST(EvolutionTest, StatisticsAreOverTheGenerationsOkJobs) {
  // A population of 5 with fixed answers per position in the batch: 4, failed, 1, 2, 10 → ok: 4, 1, 2, 10.
  EvolutionSettings settings = SettingsFor(Algorithm::kDe);
  settings.population = 5;
  Evolution evolution(settings, [](const std::vector<Genome>& genomes, std::uint64_t) {
    std::vector<Evaluation> answers = {{4.0, true}, {100.0, false}, {1.0, true}, {2.0, true}, {10.0, true}};
    answers.resize(genomes.size());
    return answers;
  });
  evolution.Initialise();
  const GenerationRecord& record = evolution.history().at(0);
  EXPECT_EQ(record.evaluations, 5u);
  EXPECT_EQ(record.failed, 1u);
  EXPECT_EQ(record.best, 10.0);
  EXPECT_EQ(record.worst, 1.0);
  EXPECT_EQ(record.mean, 17.0 / 4.0);
  EXPECT_EQ(record.median, 3.0);  // the mean of the middle two of 1, 2, 4, 10
  EXPECT_EQ(record.best_so_far, 10.0);
  EXPECT_EQ(evolution.champion().fitness, 10.0);
  EXPECT_EQ(evolution.champion().generation, 0);
}

TEST(EvolutionTest, CmaesImprovesOnASmoothFunction) {
  BatchLog log;
  Evolution evolution(SettingsFor(Algorithm::kCmaes), Logging(log, SphereOk));
  evolution.Initialise();
  for (int generation = 1; generation <= 15; ++generation) evolution.Step();
  const double start = evolution.history().front().best_so_far;
  const double end = evolution.history().back().best_so_far;
  // The error −fitness shrinks at least tenfold; the champion is near the centre.
  EXPECT_GT(end, start / 10.0) << "generation 0 best " << start << ", generation 15 best " << end;
  for (std::size_t i = 0; i < kCentre.size(); ++i) {
    EXPECT_NEAR(evolution.champion().genome[i], kCentre[i], 0.5) << "gene " << i;
  }
  // The last generation's own best is better than the first's: the population moved, not just one lucky genome.
  EXPECT_GT(evolution.history().back().best, evolution.history().front().best);
}

// ---- resuming ----

class ResumableAlgorithmTest : public ::testing::TestWithParam<Algorithm> {};

TEST_P(ResumableAlgorithmTest, ResumedFromSaveStateEqualsAnUninterruptedRun) {
  const EvolutionSettings settings = SettingsFor(GetParam());
  BatchLog whole_log;
  Evolution whole(settings, Logging(whole_log, SphereOk));
  whole.Initialise();
  for (int generation = 1; generation <= 4; ++generation) whole.Step();

  BatchLog first_log;
  Evolution first(settings, Logging(first_log, SphereOk));
  first.Initialise();
  first.Step();
  first.Step();
  const std::string state = first.SaveState();

  BatchLog resumed_log;
  Evolution resumed(settings, Logging(resumed_log, SphereOk));
  resumed.Restore(state, first.history(), first.champion(), "checkpoint.json");
  EXPECT_EQ(resumed.generation(), 2);
  resumed.Step();
  resumed.Step();

  ExpectSameHistoryButSeconds(whole.history(), resumed.history());
  ExpectSameChampion(whole.champion(), resumed.champion());
  ExpectSamePopulation(whole.population(), resumed.population());
  // The resumed run asked for exactly the jobs of generations 3 and 4.
  ASSERT_EQ(resumed_log.genomes.size(), 2u);
  EXPECT_EQ(Bits(resumed_log.genomes[0]), Bits(whole_log.genomes[3]));
  EXPECT_EQ(Bits(resumed_log.genomes[1]), Bits(whole_log.genomes[4]));
}

// A state holding infinite fitness values (and, as pagmo's CMA-ES sometimes saves, NaN) reads back: Boost's plain
// text archive writes "inf" and "nan" but fails to read them, which made resuming fail at random.
TEST(EvolutionTest, AStateHoldingNonFiniteFitnessReadsBack) {
  const EvolutionSettings settings = SettingsFor(Algorithm::kCmaes);
  const auto infinite_above_half = [](const Genome& genome) {
    return genome[0] > 0.5 ? Evaluation{-INFINITY, true} : SphereOk(genome);
  };
  BatchLog first_log;
  Evolution first(settings, Logging(first_log, infinite_above_half));
  first.Initialise();
  first.Step();
  const std::string state = first.SaveState();
  ASSERT_THAT(state, HasSubstr("inf")) << "the test must put an infinite fitness into the state";

  BatchLog resumed_log;
  Evolution resumed(settings, Logging(resumed_log, infinite_above_half));
  resumed.Restore(state, first.history(), first.champion(), "checkpoint.json");
  ExpectSamePopulation(first.population(), resumed.population());
}

INSTANTIATE_TEST_SUITE_P(Algorithms, ResumableAlgorithmTest,
                         ::testing::Values(Algorithm::kCmaes, Algorithm::kXnes, Algorithm::kSga, Algorithm::kDe),
                         [](const ::testing::TestParamInfo<Algorithm>& param) { return AlgorithmName(param.param); });

// pagmo 2.18's pso_gen keeps its particles' velocities between generations but leaves them (and its memory flag) out
// of its saved state: restored, it searches differently. When this fails, pagmo saves them: allow resuming pso_gen
// (CheckResumable) and add it to ResumableAlgorithmTest.
TEST(EvolutionTest, PagmoLeavesPsoGensVelocitiesOutOfItsSavedState) {
  const EvolutionSettings settings = SettingsFor(Algorithm::kPsoGen);
  Evolution evolution(settings, [](const std::vector<Genome>&, std::uint64_t) { return std::vector<Evaluation>{}; });
  pagmo::population plain(pagmo::problem{DirectProblem{&evolution, nullptr}}, 8u, 11u);
  pagmo::algorithm algorithm = MakeAlgorithm(settings);
  plain = algorithm.evolve(plain);  // a first generation fills its memory
  std::ostringstream saved;
  {
    boost::archive::text_oarchive archive(saved);
    archive << algorithm;
  }
  pagmo::algorithm restored;
  {
    std::istringstream text(saved.str());
    boost::archive::text_iarchive archive(text);
    archive >> restored;
  }
  const pagmo::population next = algorithm.evolve(plain);
  const pagmo::population next_restored = restored.evolve(plain);
  EXPECT_NE(Bits(next_restored.get_x()), Bits(next.get_x()));
}

TEST(EvolutionTest, APsoGenRunIsNotResumedAndTheErrorSaysWhy) {
  BatchLog log;
  Evolution first(SettingsFor(Algorithm::kPsoGen), Logging(log, SphereOk));
  first.Initialise();
  first.Step();
  Evolution resumed(SettingsFor(Algorithm::kPsoGen), Logging(log, SphereOk));
  EXPECT_THAT(
      InputErrorOf([&] { resumed.Restore(first.SaveState(), first.history(), first.champion(), "run/x.json"); }),
      AllOf(HasSubstr("run/x.json"), HasSubstr("pso_gen run cannot be resumed"), HasSubstr("velocities")));
  for (const Algorithm algorithm : {Algorithm::kCmaes, Algorithm::kXnes, Algorithm::kSga, Algorithm::kDe}) {
    EXPECT_NO_THROW(CheckResumable(algorithm, "x")) << AlgorithmName(algorithm);
  }
}

// ---- the gene mapping ----

TEST(EvolutionTest, GenomeOfMapsTheUnitBoxOntoTheBoundsAndClamps) {
  Evolution evolution(SettingsFor(Algorithm::kCmaes),
                      [](const std::vector<Genome>&, std::uint64_t) { return std::vector<Evaluation>{}; });
  // Bounds: [-2, 3], [0, 10], [-1, 1].
  EXPECT_EQ(evolution.GenomeOf({0.0, 0.0, 0.0}), (Genome{-2.0, 0.0, -1.0}));
  EXPECT_EQ(evolution.GenomeOf({1.0, 1.0, 1.0}), (Genome{3.0, 10.0, 1.0}));
  EXPECT_EQ(evolution.GenomeOf({0.5, 0.25, 0.75}), (Genome{0.5, 2.5, 0.5}));
  EXPECT_EQ(evolution.GenomeOf({-0.5, 1.5, 2.0}), (Genome{-2.0, 10.0, 1.0}));  // outside the box: clamped

  EXPECT_EQ(evolution.DecisionVectorOf({-2.0, 0.0, -1.0}), (pagmo::vector_double{0.0, 0.0, 0.0}));
  EXPECT_EQ(evolution.DecisionVectorOf({3.0, 10.0, 1.0}), (pagmo::vector_double{1.0, 1.0, 1.0}));
  EXPECT_EQ(evolution.DecisionVectorOf({0.5, 2.5, 0.5}), (pagmo::vector_double{0.5, 0.25, 0.75}));
  EXPECT_EQ(evolution.DecisionVectorOf({-7.0, 11.0, 0.0}), (pagmo::vector_double{0.0, 1.0, 0.5}));  // clamped

  const Genome genome = {0.3, 7.1, -0.9};
  const Genome back = evolution.GenomeOf(evolution.DecisionVectorOf(genome));
  for (std::size_t i = 0; i < genome.size(); ++i) EXPECT_NEAR(back[i], genome[i], 1e-12) << "gene " << i;
}

TEST(EvolutionTest, TheStartGenomeIsTheFirstIndividualAndTheRestAreInTheBounds) {
  BatchLog log;
  Evolution evolution(SettingsFor(Algorithm::kSga), Logging(log, SphereOk));
  evolution.Initialise();
  ASSERT_EQ(log.genomes.size(), 1u);
  ASSERT_EQ(log.genomes[0].size(), 8u);
  EXPECT_EQ(log.genomes[0][0], (Genome{0.0, 5.0, 0.25}));
  const std::vector<GeneBounds>& bounds = evolution.settings().bounds;
  for (const Genome& genome : log.genomes[0]) {
    for (std::size_t i = 0; i < genome.size(); ++i) {
      EXPECT_GE(genome[i], bounds[i].low);
      EXPECT_LE(genome[i], bounds[i].high);
    }
  }
  // Seeded: another Evolution with the same settings draws the same population; another seed, another one.
  BatchLog again_log;
  Evolution again(SettingsFor(Algorithm::kSga), Logging(again_log, SphereOk));
  again.Initialise();
  EXPECT_EQ(Bits(again_log.genomes[0]), Bits(log.genomes[0]));
  EvolutionSettings other = SettingsFor(Algorithm::kSga);
  other.seed = 6;
  BatchLog other_log;
  Evolution reseeded(other, Logging(other_log, SphereOk));
  reseeded.Initialise();
  EXPECT_NE(Bits(other_log.genomes[0][1]), Bits(log.genomes[0][1]));
}

}  // namespace
}  // namespace orcs::evolve
