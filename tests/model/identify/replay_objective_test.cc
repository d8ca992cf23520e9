// The objective every fit minimises (model/identify/replay_objective.h) on the analytic stand-in: how it pools runs
// by their samples, scores a failed replay, and turns a point's bound into each run's stop_above.
#include "model/identify/replay_objective.h"

#include <gtest/gtest.h>

#include "tests/model/identify/analytic_evaluator.h"

namespace orcs::identify {
namespace {

using test::AnalyticEvaluator;
using test::AnalyticRun;

// Each run's bound is the RMS past which it alone puts the pooled error above the point's bound.
TEST(ReplayObjectiveTest, APointsBoundBecomesEachRunsStopAboveAndItsLowerBoundExceedsIt) {
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

TEST(ReplayObjectiveTest, TheObjectivePoolsRunsBySamplesAndScoresAFailedReplayAsFailed) {
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
TEST(ReplayObjectiveTest, TheAbsoluteLossPoolsMeanAbsoluteErrorsAndBoundsRunsInThatNorm) {
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
