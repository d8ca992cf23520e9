// The fitter on a cheap analytic system instead of simulations (tests/model/identify/analytic_evaluator.h): the
// optimiser, the unit-box mapping (log-scaled and linear), the race, the local stages from several starts and the
// re-search beyond a bound, without a broker or a physics engine.
#include "model/identify/model_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>

#include "tests/model/identify/analytic_evaluator.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace orcs::identify {
namespace {

using test::AnalyticEvaluator;
using test::AnalyticRun;
using test::kParameters;
using test::kTrueA;
using test::kTrueB;

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
  EXPECT_LE(with_islands.mse, plain.mse + 1e-12);  // both at the optimum: equal up to rounding
  EXPECT_NEAR(with_islands.values[0], kTrueA, 0.02 * kTrueA);
  EXPECT_NEAR(with_islands.values[1], kTrueB, 0.02);
  // Each island asks for at least one point per generation, and each is a replay of the one run.
  EXPECT_GE(with_islands.evaluations, plain.evaluations + 3 * 20);
  EXPECT_EQ(static_cast<std::uint64_t>(with_islands.evaluations), evaluator.replays_run() - before);

  const FitOutcome again = Fit(objective, kParameters, island_options);
  EXPECT_EQ(again.values, with_islands.values);
  EXPECT_EQ(again.mse, with_islands.mse);
}

// A race that lets a candidate go on changes its swarm in nothing: the question is asked once, of the point a polish
// reached from the swarm's best after 10 generations, and that point is one more start for the local stages, so the
// fit ends at least as well as without the race.
TEST(ModelFitTest, ARaceThatKeepsAFitLeavesItsSwarmAsItWasAndAddsItsPolishedPoint) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 1.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions short_swarm;
  short_swarm.generations = 12;
  const FitOutcome plain = Fit(objective, kParameters, short_swarm);
  FitOptions raced = short_swarm;
  std::vector<double> asked_at;
  raced.abandon = [&](const std::vector<double>&, double mse) -> std::string {
    asked_at.push_back(mse);
    return "";
  };
  const FitOutcome kept = Fit(objective, kParameters, raced);
  ASSERT_EQ(asked_at.size(), 1u);
  EXPECT_NEAR(asked_at[0], 1.0, 0.01) << "asked of the polished point: the analytic optimum leaves its floor, 1 deg²";
  EXPECT_FALSE(kept.abandoned);
  EXPECT_LE(kept.mse, plain.mse);
  EXPECT_EQ(kept.generations, 12);
  EXPECT_GT(kept.local_starts, plain.local_starts);  // the race's polish
}

// A fit is abandoned only once its point has converged: the race polishes the swarm's best point after 10
// generations and asks of that. Here no point can beat the limit (a floor of 3° is 9 deg²): the fit is abandoned
// with the polished point, its swarm stopped after 10 generations.
TEST(ModelFitTest, TheRaceAbandonsAFitOnlyAfterItsBestPointHasConverged) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 3.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions options;
  std::vector<double> asked_at;  // the objective of each point the question was asked about
  options.abandon = [&](const std::vector<double>& values, double mse) -> std::string {
    EXPECT_EQ(values.size(), 2u);
    asked_at.push_back(mse);
    return mse > 8.0 ? "above the limit" : "";
  };
  const FitOutcome abandoned = Fit(objective, kParameters, options);
  EXPECT_TRUE(abandoned.abandoned);
  ASSERT_EQ(asked_at.size(), 1u);
  EXPECT_NE(abandoned.convergence.find("abandoned after 10 generations, converged from its best point: above the "
                                       "limit"),
            std::string::npos)
      << abandoned.convergence;
  EXPECT_TRUE(abandoned.converged) << abandoned.convergence;
  EXPECT_EQ(abandoned.generations, 10);
  EXPECT_NEAR(abandoned.mse, 9.0, 0.01);
  EXPECT_EQ(abandoned.mse, asked_at[0]);
  // The initial 16 particles, the start in place of the worst, ten generations of 16, then the polish.
  EXPECT_EQ(static_cast<std::uint64_t>(abandoned.evaluations), evaluator.replays_run());
  EXPECT_GT(abandoned.evaluations, 16 + 1 + 10 * 16);
  ASSERT_EQ(abandoned.ci95.size(), 2u);
  EXPECT_TRUE(std::isnan(abandoned.ci95[0]));
}

// Where the race's polish cannot converge (here: an evaluator without residuals, so no polish can run), the compass
// search goes on from its point until its step has shrunk: the fit is judged, and abandoned, only there.
TEST(ModelFitTest, WhereThePolishCannotConvergeTheRaceJudgesAfterTheCompassSearch) {
  class NoResiduals : public AnalyticEvaluator {
   public:
    std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
      std::vector<ReplayOutcome> outcomes = AnalyticEvaluator::Replay(requests);
      for (ReplayOutcome& outcome : outcomes) outcome.columns.clear();
      return outcomes;
    }
  } evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 3.0)};
  const ReplayObjective objective(evaluator, runs, {});
  FitOptions options;
  std::vector<double> asked_at;
  options.abandon = [&](const std::vector<double>&, double mse) -> std::string {
    asked_at.push_back(mse);
    return "above the limit";
  };
  const FitOutcome abandoned = Fit(objective, kParameters, options);
  ASSERT_EQ(asked_at.size(), 1u);
  EXPECT_TRUE(abandoned.abandoned);
  EXPECT_TRUE(abandoned.converged) << abandoned.convergence;
  EXPECT_NE(abandoned.convergence.find("the local search's step fell below 0.2 %"), std::string::npos)
      << abandoned.convergence;
  EXPECT_NEAR(asked_at[0], 9.0, 0.05);  // the compass search reached the floor
}

// Two basins: a wide one around /A = 0.3 that leaves 2°, and a narrow one around /A = 3 that leaves nothing. A fit
// whose swarm stays in the wide basin ends there; given a start in the narrow one (as the scan offers its points),
// its local stages from both starts find the better.
class TwoBasins : public ReplayEvaluator {
 public:
  /// The RMS each basin leaves at its bottom, degrees.
  explicit TwoBasins(double wide_floor = 2.0, double narrow_floor = 0.0)
      : wide_floor_(wide_floor), narrow_floor_(narrow_floor) {}

  std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
    std::vector<ReplayOutcome> outcomes;
    for (const ReplayRequest& request : requests) {
      std::map<std::string, double> values;
      for (const auto& [path, value] : request.overrides) values[path] = std::stod(value);
      const double wide = 10.0 * std::log(values["/A"] / 0.3);
      const double narrow = 100.0 * std::log(values["/A"] / 3.0);
      const double db = 10.0 * (values["/B"] - kTrueB);
      const bool in_narrow =
          narrow * narrow + narrow_floor_ * narrow_floor_ < wide * wide + wide_floor_ * wide_floor_;
      const double da = in_narrow ? narrow : wide;
      const double floor = in_narrow ? narrow_floor_ : wide_floor_;
      ReplayOutcome outcome;
      outcome.ok = true;
      outcome.error = std::sqrt(da * da + db * db + floor * floor);
      if (request.log) {
        std::vector<double> angles = {0.0};
        for (std::size_t k = 1; k <= request.run->samples; ++k) {
          angles.push_back(test::AnalyticResidual(da, db, floor, k, request.run->samples));
        }
        outcome.columns.emplace_back("/Sim/Analytic/M/JointAngle", std::move(angles));
      }
      outcomes.push_back(outcome);
    }
    replays_ += requests.size();
    return outcomes;
  }
  std::uint64_t replays_run() const override { return replays_; }

 private:
  double wide_floor_;
  double narrow_floor_;
  std::atomic<std::uint64_t> replays_{0};
};

TEST(ModelFitTest, LocalStagesFromSeveralStartsFindTheBasinTheSwarmMissed) {
  TwoBasins evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  std::vector<FitParameter> parameters = kParameters;
  parameters[0].start = 0.25;
  FitOptions options;
  options.generations = 2;
  const FitOutcome swarm_only = Fit(objective, parameters, options);
  ASSERT_NEAR(swarm_only.values[0], 0.3, 0.03) << "the premise: the swarm stays in the wide basin";
  EXPECT_NEAR(swarm_only.mse, 4.0, 0.1);

  options.starts = {{{3.1, 0.0}, objective.Losses({{{"/A", "3.1"}, {"/B", "0"}}})[0]}};
  const FitOutcome both = Fit(objective, parameters, options);
  EXPECT_NEAR(both.values[0], 3.0, 0.03);
  EXPECT_NEAR(both.values[1], kTrueB, 0.02);
  EXPECT_LT(both.mse, 1.0);  // the wide basin leaves 4 deg²; the compass search stops within 0.2 % of the range
  EXPECT_GE(both.local_starts, 2);
}

// With FitOptions::least_change (orcs-gap's refit), two minima that fit alike (within 1 %: the wide basin leaves
// 1.000°, the narrow one 0.997°) are told apart by what the data cannot: the fit keeps the one that moved least from
// its start (here the wide basin, nearer the start at 0.25). When one fits clearly better (0.9°: 19 % less), it wins
// wherever it lies; without the option the best always does.
TEST(ModelFitTest, WithLeastChangeOfMinimaThatFitAlikeTheFitKeepsTheOneNearestItsStart) {
  const auto fit_with_floors = [](double wide_floor, double narrow_floor, bool least_change) {
    TwoBasins evaluator(wide_floor, narrow_floor);
    const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
    const ReplayObjective objective(evaluator, runs, {});
    std::vector<FitParameter> parameters = kParameters;
    parameters[0].start = 0.25;
    FitOptions options;
    options.generations = 2;
    options.least_change = least_change;
    options.starts = {{{3.1, 0.0}, objective.Losses({{{"/A", "3.1"}, {"/B", "0"}}})[0]}};
    return Fit(objective, parameters, options);
  };
  const FitOutcome alike = fit_with_floors(1.0, 0.997, true);
  EXPECT_NEAR(alike.values[0], 0.3, 0.03);
  EXPECT_NEAR(alike.mse, 1.0, 0.01);
  EXPECT_GE(alike.local_starts, 2);  // the narrow basin was searched too, and set aside
  const FitOutcome better = fit_with_floors(1.0, 0.9, true);
  EXPECT_NEAR(better.values[0], 3.0, 0.03);
  EXPECT_NEAR(better.mse, 0.81, 0.01);
  const FitOutcome best = fit_with_floors(1.0, 0.997, false);  // without the option: the best, however near
  EXPECT_NEAR(best.values[0], 3.0, 0.03);
}

// The race judges the best point the fit knows, not only its swarm's: a swarm still in the wide basin after ten
// generations (the refit's basin, 4 deg²) would be abandoned by a limit of 3 deg², but the scan's start in the
// narrow basin, which already fits better (0.44 deg²), is polished too: the truth, and the fit is kept.
TEST(ModelFitTest, TheRaceAlsoPolishesTheScansBestStartBeforeItJudges) {
  TwoBasins evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  std::vector<FitParameter> parameters = kParameters;
  parameters[0].start = 0.25;
  FitOptions options;
  options.generations = 12;
  options.abandon_after = 10;
  std::vector<double> asked_at;
  options.abandon = [&](const std::vector<double>&, double mse) -> std::string {
    asked_at.push_back(mse);
    return mse > 3.0 ? "above the limit" : "";
  };
  const FitOutcome swarm_only = Fit(objective, parameters, options);
  ASSERT_TRUE(swarm_only.abandoned) << "the premise: judged from its swarm alone, the fit is abandoned";
  ASSERT_NEAR(asked_at.back(), 4.0, 0.1);

  options.starts = {{{3.02, 0.3}, objective.Losses({{{"/A", "3.02"}, {"/B", "0.3"}}})[0]}};
  asked_at.clear();
  const FitOutcome kept = Fit(objective, parameters, options);
  EXPECT_FALSE(kept.abandoned) << kept.convergence;
  ASSERT_EQ(asked_at.size(), 1u);
  EXPECT_LT(asked_at[0], 0.1);  // the race asked about the narrow basin's polished point
  EXPECT_NEAR(kept.values[0], 3.0, 0.03);
}

// A parameter that ends at a bound of its range: a log-scaled one is re-searched in a range four times wider on that
// side and reported beyond the catalogue's range when it moves past it; a linear one cannot widen and is reported at
// its bound. Here the truth (/A = 2, /B = 0.3) lies above both ranges.
TEST(ModelFitTest, AParameterAtABoundIsReSearchedBeyondItOrReported) {
  AnalyticEvaluator evaluator;
  const std::vector<ReplayRun> runs = {AnalyticRun("one", 100, 0.0)};
  const ReplayObjective objective(evaluator, runs, {});
  const std::vector<FitParameter> narrow = {{"/A", "", 0.1, 1.0, true, 0.5}, {"/B", "", -1.0, 0.0, false, -0.5}};
  const FitOutcome outcome = Fit(objective, narrow, FitOptions{});
  ASSERT_EQ(outcome.bounds.size(), 2u);
  EXPECT_EQ(outcome.bounds[0], BoundState::kBeyond);
  EXPECT_NEAR(outcome.values[0], kTrueA, 0.02 * kTrueA);
  EXPECT_EQ(outcome.bounds[1], BoundState::kAtUpper);
  EXPECT_NEAR(outcome.values[1], 0.0, 1e-9);
  // Inside their ranges, parameters are reported inside.
  const FitOutcome inside = Fit(objective, kParameters, FitOptions{});
  EXPECT_EQ(inside.bounds, (std::vector<BoundState>{BoundState::kInside, BoundState::kInside}));
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




}  // namespace
}  // namespace orcs::identify
