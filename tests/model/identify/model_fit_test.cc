// The fitter on a cheap analytic system instead of simulations: a ReplayEvaluator stand-in answers each replay
// with an RMS error (degrees) computed from its overrides, so the tests check the optimiser, the unit-box
// mapping (log-scaled and linear) and the pooling of runs without a broker or a physics engine.
#include "model/identify/model_fit.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace orcs::identify {
namespace {

// The hidden truth: /A = 2.0 (searched on a log scale over 0.1…10), /B = 0.3 (linear over −1…1).
constexpr double kTrueA = 2.0;
constexpr double kTrueB = 0.3;

// A run's RMS error: 10° per unit of log-distance in A and per unit of distance in B, plus the run's own floor
// (what no parameter can explain). A replay whose /A is negative "goes unstable".
class AnalyticEvaluator : public ReplayEvaluator {
 public:
  std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
    std::vector<ReplayOutcome> outcomes;
    for (const ReplayRequest& request : requests) {
      std::map<std::string, double> values;
      for (const auto& [path, value] : request.overrides) values[path] = std::stod(value);
      const double a = values.count("/A") ? values["/A"] : 1.0;
      const double b = values.count("/B") ? values["/B"] : 0.0;
      const double floor = request.run->scenario.value("floor_deg", 0.0);
      ReplayOutcome outcome;
      outcome.ok = a >= 0;
      if (outcome.ok) {
        const double da = 10.0 * std::log(a / kTrueA), db = 10.0 * (b - kTrueB);
        outcome.error = std::sqrt(da * da + db * db + floor * floor);
        // A replay past its bound stops with the least lower bound it may give: just above the bound.
        if (outcome.error > request.stop_above) {
          outcome.error = std::nextafter(request.stop_above, std::numeric_limits<double>::infinity());
          outcome.stopped_early = true;
          ++stopped_;
        }
      }
      outcomes.push_back(outcome);
    }
    replays_ += requests.size();
    return outcomes;
  }
  std::uint64_t replays_run() const override { return replays_; }
  std::uint64_t replays_stopped_early() const override { return stopped_; }

 private:
  std::atomic<std::uint64_t> replays_{0};
  std::atomic<std::uint64_t> stopped_{0};
};

ReplayRun AnalyticRun(const std::string& name, std::size_t samples, double floor_deg) {
  ReplayRun run;
  run.name = name;
  run.source = name + ".csv";
  run.samples = samples;
  run.scenario = {{"agent", "Analytic"}, {"duration", 1.0}, {"floor_deg", floor_deg}};
  return run;
}

const std::vector<FitParameter> kParameters = {{"/A", "", 0.1, 10.0, true, 0.5}, {"/B", "", -1.0, 1.0, false, -0.5}};

TEST(ModelFitTest, FindsTheAnalyticOptimumFromAFarStartAndSaysItConverged) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  const FitOutcome outcome = Fit(objective, kParameters, FitOptions{});
  ASSERT_EQ(outcome.values.size(), 2u);
  EXPECT_NEAR(outcome.values[0], kTrueA, 0.02 * kTrueA);
  EXPECT_NEAR(outcome.values[1], kTrueB, 0.02);
  EXPECT_LT(outcome.mse, 0.05);  // deg²
  EXPECT_TRUE(outcome.converged) << outcome.convergence;
  // One run: one replay per point (a point asked for twice would be answered from the cache; none is here).
  EXPECT_EQ(static_cast<std::uint64_t>(outcome.evaluations), evaluator.replays_run());
}

TEST(ModelFitTest, TheSameInputsGiveTheSameFitAndAnotherSeedSearchesElsewhere) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions short_fit;
  short_fit.generations = 3;
  const FitOutcome a = Fit(objective, kParameters, short_fit);
  const FitOutcome b = Fit(objective, kParameters, short_fit);
  short_fit.seed = 2;
  const FitOutcome c = Fit(objective, kParameters, short_fit);
  EXPECT_EQ(a.values, b.values);
  EXPECT_EQ(a.mse, b.mse);
  EXPECT_NE(a.values, c.values);
}

// CMA-ES islands (FitOptions::islands) only add a second start for the local stages: after a swarm too short to
// settle, the fit with islands is at least as good as without, every replay is counted, and the islands, though
// they run side by side, give the same fit every time.
TEST(ModelFitTest, IslandsAddASecondStartThatCanOnlyImproveTheFitAndStayReproducible) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions plain_options;
  plain_options.generations = 1;
  const FitOutcome plain = Fit(objective, kParameters, plain_options);

  FitOptions island_options = plain_options;
  island_options.islands = 3;
  island_options.island_generations = 20;
  const std::uint64_t before = evaluator.replays_run();
  const FitOutcome with_islands = Fit(objective, kParameters, island_options);
  EXPECT_LE(with_islands.mse, plain.mse);
  EXPECT_NEAR(with_islands.values[0], kTrueA, 0.02 * kTrueA);
  EXPECT_NEAR(with_islands.values[1], kTrueB, 0.02);
  // Each island asks for at least one point per generation, and each is a replay of the one run.
  EXPECT_GE(with_islands.evaluations, plain.evaluations + 3 * 20);
  EXPECT_EQ(static_cast<std::uint64_t>(with_islands.evaluations), evaluator.replays_run() - before);

  const FitOutcome again = Fit(objective, kParameters, island_options);
  EXPECT_EQ(again.values, with_islands.values);
  EXPECT_EQ(again.mse, with_islands.mse);
}

TEST(ModelFitTest, AFitTheRaceKeepsSearchesExactlyAsWithoutTheRace) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 1.0)};
  const ReplayObjective objective(evaluator, runs, {});
  const FitOutcome plain = Fit(objective, kParameters, FitOptions{});
  FitOptions raced;
  int asked = 0;
  raced.abandon = [&](const std::vector<double>&, double) -> std::string {
    ++asked;
    return "";
  };
  const FitOutcome kept = Fit(objective, kParameters, raced);
  EXPECT_EQ(asked, 1);
  EXPECT_FALSE(kept.abandoned);
  EXPECT_EQ(kept.values, plain.values);
  EXPECT_EQ(kept.mse, plain.mse);
  EXPECT_EQ(kept.generations, 40);
  EXPECT_GT(kept.evaluations, plain.evaluations);  // the quick look's replays
}

TEST(ModelFitTest, AFitItsAbandonQuestionRejectsStopsAfterItsFirstGenerationsWithoutLocalStages) {
  AnalyticEvaluator evaluator;
  // The floor of 3° is 9 deg² that no parameter removes.
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 3.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions options;
  int asked = 0;
  double limit = 8.0;
  options.abandon = [&](const std::vector<double>& values, double mse) -> std::string {
    ++asked;
    EXPECT_EQ(values.size(), 2u);
    return mse > limit ? "above the limit" : "";
  };
  options.abandon_after = 10;
  const FitOutcome abandoned = Fit(objective, kParameters, options);
  EXPECT_TRUE(abandoned.abandoned);
  EXPECT_EQ(asked, 1);
  EXPECT_NE(abandoned.convergence.find("abandoned after 10 generations: above the limit"), std::string::npos)
      << abandoned.convergence;
  EXPECT_FALSE(abandoned.converged);
  EXPECT_EQ(abandoned.generations, 10);
  EXPECT_GT(abandoned.mse, 8.0);
  // The initial 16 particles, the start point put in place of the worst, the quick local look (at least one
  // point), ten generations of 16, and nothing after them.
  EXPECT_EQ(static_cast<std::uint64_t>(abandoned.evaluations), evaluator.replays_run());
  const int look = abandoned.evaluations - (16 + 1 + 10 * 16);
  EXPECT_GE(look, 1);  // the analytic evaluator logs no columns: the look stops at its first point
  EXPECT_LE(look, 40);
  ASSERT_EQ(abandoned.ci95.size(), 2u);
  EXPECT_TRUE(std::isnan(abandoned.ci95[0]));

  EXPECT_FALSE(abandoned.abandoned_unmoved);
  EXPECT_EQ(abandoned.convergence.find("not changed since"), std::string::npos)
      << "its swarm improved on its first generation: " << abandoned.convergence;

  limit = 9.5;  // reachable: the fit goes on to its local stages
  const FitOutcome kept = Fit(objective, kParameters, options);
  EXPECT_FALSE(kept.abandoned);
  EXPECT_NEAR(kept.mse, 9.0, 0.05);
  EXPECT_TRUE(kept.converged) << kept.convergence;
}

// A swarm whose best has not changed since its first generation may not have started to search; the race's
// verdict says so, with the option that fits it to the end. Here the start is the optimum: nothing improves on it.
TEST(ModelFitTest, AnAbandonedFitWhoseSwarmNeverImprovedSaysItsSearchMayNotHaveStarted) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 3.0)};
  const ReplayObjective objective(evaluator, runs, {});
  std::vector<FitParameter> at_optimum = kParameters;
  at_optimum[0].start = kTrueA;
  at_optimum[1].start = kTrueB;
  FitOptions options;
  options.abandon = [](const std::vector<double>&, double mse) -> std::string {
    return mse > 8.0 ? "above the limit" : "";
  };
  const FitOutcome abandoned = Fit(objective, at_optimum, options);
  ASSERT_TRUE(abandoned.abandoned);
  EXPECT_TRUE(abandoned.abandoned_unmoved);
  EXPECT_NEAR(abandoned.mse, 9.0, 1e-9);
  EXPECT_NE(abandoned.convergence.find("above the limit; its best had not changed since the swarm's first "
                                       "generation, so its search may not have started (--no-race"),
            std::string::npos)
      << abandoned.convergence;
}

// Replays stopped at their point's bound (the particle's best in the swarm, the current point in the compass search)
// answer with a lower bound just above it; the fit must not notice: the same values, error and evaluations as with
// every replay run to its end, with and without the race, over two runs of unequal length.
TEST(ModelFitTest, ReplaysStoppedEarlyLeaveTheFitExactlyAsWithoutThem) {
  for (const bool raced : {false, true}) {
    SCOPED_TRACE(raced ? "raced" : "not raced");
    AnalyticEvaluator evaluator;
    const std::vector<ReplayRun> runs = {AnalyticRun("small", 100, 1.0), AnalyticRun("large", 300, 0.5)};
    const ReplayObjective objective(evaluator, runs, {});
    FitOptions whole;
    whole.stop_replays_early = false;
    if (raced) whole.abandon = [](const std::vector<double>&, double) { return std::string(); };
    const FitOutcome reference = Fit(objective, kParameters, whole);
    ASSERT_EQ(evaluator.replays_stopped_early(), 0u);
    FitOptions early = whole;
    early.stop_replays_early = true;
    const FitOutcome stopped = Fit(objective, kParameters, early);
    EXPECT_GT(evaluator.replays_stopped_early(), static_cast<std::uint64_t>(stopped.evaluations) / 4);
    EXPECT_EQ(stopped.values, reference.values);
    EXPECT_EQ(stopped.mse, reference.mse);
    EXPECT_EQ(stopped.evaluations, reference.evaluations);
    EXPECT_EQ(stopped.converged, reference.converged);
    EXPECT_EQ(stopped.convergence, reference.convergence);
  }
}

// Each run's bound is the RMS past which it alone puts the pooled error above the point's bound.
TEST(ModelFitTest, APointsBoundBecomesEachRunsStopAboveAndItsLowerBoundExceedsIt) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("small", 100, 1.0), AnalyticRun("large", 300, 3.0)};
  const ReplayObjective objective(evaluator, runs, {});
  // At the optimum the pooled error is 7 deg²: a bound of 8 stops nothing, a bound of 2 stops the large run
  // (its 3² · 300 / 400 = 6.75 deg² alone exceeds 2).
  const std::vector<std::vector<Override>> optimum = {{{"/A", "2"}, {"/B", "0.3"}}};
  EXPECT_DOUBLE_EQ(objective.Losses(optimum, {8.0})[0], 7.0);
  EXPECT_EQ(evaluator.replays_stopped_early(), 0u);
  const double lower = objective.Losses(optimum, {2.0})[0];
  EXPECT_GT(evaluator.replays_stopped_early(), 0u);
  EXPECT_GT(lower, 2.0);
  EXPECT_LE(lower, 7.0);
}

TEST(ModelFitTest, TheObjectivePoolsRunsBySamplesAndScoresAFailedReplayAsFailed) {
  AnalyticEvaluator evaluator;
  // At the optimum each run's error is its floor: pooled over samples, (100·1² + 300·3²) / 400 = 7 deg².
  const std::vector<ReplayRun> runs = {AnalyticRun("small", 100, 1.0), AnalyticRun("large", 300, 3.0)};
  const ReplayObjective objective(evaluator, runs, {{"/Fixed", "1"}});
  const std::vector<double> errors =
      objective.Losses({{{"/A", "2"}, {"/B", "0.3"}}, {{"/A", "-1"}, {"/B", "0.3"}}});
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_DOUBLE_EQ(errors[0], 7.0);
  EXPECT_EQ(errors[1], ReplayObjective::kFailedPoint);
  EXPECT_EQ(evaluator.replays_run(), 4u);  // two points × two runs, one batch
}

// The absolute loss pools each run's mean absolute error by its samples, and a point's bound becomes each run's
// bound in that norm: at the optimum (100·1 + 300·3) / 400 = 2.5°; a bound of 2 stops the large run (3° × 300 / 400
// = 2.25° alone exceeds it), a bound of 2.6 stops nothing.
TEST(ModelFitTest, TheAbsoluteLossPoolsMeanAbsoluteErrorsAndBoundsRunsInThatNorm) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("small", 100, 1.0), AnalyticRun("large", 300, 3.0)};
  const ReplayObjective objective(evaluator, runs, {}, Loss::kAbsolute);
  const std::vector<std::vector<Override>> optimum = {{{"/A", "2"}, {"/B", "0.3"}}};
  EXPECT_DOUBLE_EQ(objective.Losses(optimum, {2.6})[0], 2.5);
  EXPECT_EQ(evaluator.replays_stopped_early(), 0u);
  const double lower = objective.Losses(optimum, {2.0})[0];
  EXPECT_EQ(evaluator.replays_stopped_early(), 1u);
  EXPECT_GT(lower, 2.0);
  EXPECT_LE(lower, 2.5);
}

}  // namespace
}  // namespace orcs::identify
