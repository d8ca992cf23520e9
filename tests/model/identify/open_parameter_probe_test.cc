// Parameters the fit runs leave open (model/identify/open_parameter_probe.h), on an analytic stand-in for the
// pendulum's LuGre case: the fit run barely sees a stiffness /S (as the fit run barely sees the bristles), the
// held-out run is replayed well only when /S is above a threshold (a stick-slip the held-out motion crosses). The
// probe must keep the fitted point's fit, let the held-out run choose among the values that fit as well, and never
// choose a value that fits the fit run worse, however well it holds out.
#include "model/identify/open_parameter_probe.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "model/identify/replay_objective.h"

namespace orcs::identify {
namespace {

constexpr double kThreshold = 200.0;  // held out, /S below this sticks where the measured run slips

// The fit run's RMS error is the noise (0.2°) plus what `fit_penalty_above` adds past that /S; the held-out run's is
// 0.25° at /S ≥ kThreshold and 3.3° below. /A moves both a little, so that it is "fitted".
class StickSlipEvaluator : public ReplayEvaluator {
 public:
  explicit StickSlipEvaluator(double fit_penalty_above = 1e9) : fit_penalty_above_(fit_penalty_above) {}

  std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
    std::vector<ReplayOutcome> outcomes;
    for (const ReplayRequest& request : requests) {
      std::map<std::string, double> values{{"/A", 1.0}, {"/S", 1.0}};
      for (const auto& [path, value] : request.overrides) values[path] = std::stod(value);
      const double a = 0.5 * std::abs(values["/A"] - 1.0);
      const double s = values["/S"];
      ReplayOutcome outcome;
      outcome.ok = true;
      if (request.run->scenario.value("kind", "") == "fit") {
        outcome.error = 0.2 + a + 1e-5 * s + (s > fit_penalty_above_ ? 5.0 : 0.0);
      } else {
        outcome.error = a + (s >= kThreshold ? 0.25 : 3.3);
      }
      outcomes.push_back(outcome);
    }
    replays_ += requests.size();
    return outcomes;
  }
  std::uint64_t replays_run() const override { return replays_; }

 private:
  double fit_penalty_above_;
  std::atomic<std::uint64_t> replays_{0};
};

ReplayRun Run(const std::string& kind) {
  static MeasuredRun measured;
  ReplayRun run;
  run.name = kind;
  run.run = &measured;
  run.channels = {"M"};
  run.samples = 100;
  run.scenario = {{"kind", kind}};
  return run;
}

const std::vector<FitParameter> kParameters = {{"/A", "1", 0.1, 10.0, true, 1.0},
                                               {"/S", "N·m/rad", 1.0, 1000.0, true, 5.0}};

struct Probe {
  std::vector<ReplayRun> fit{Run("fit")};
  std::vector<ReplayRun> holdout{Run("held")};

  // The fit's point: /A at its truth, /S at 144.8 ± 264 (open), losses as the evaluator gives them there.
  OpenProbeResult At(StickSlipEvaluator& replays, std::vector<bool> identified = {true, false},
                     std::size_t first_probed = 0) {
    const std::vector<double> values = {1.0, 144.8};
    const std::vector<Override> point = OverridesOf(kParameters, values);
    const double fit_loss = ReplayObjective(replays, fit, {}).Losses({point})[0];
    const double holdout_loss = ReplayObjective(replays, holdout, {}).Losses({point})[0];
    return ProbeOpenParameters(replays, fit, holdout, kParameters, {}, first_probed, values, {0.01, 264.0},
                               identified, fit_loss, holdout_loss, {Loss::kSquared, 1.118});
  }
};

TEST(ProbeValuesTest, SpanTheIntervalAtHalfAndFullWidthWithoutTheValueItself) {
  const std::vector<double> values = ProbeValues(kParameters[1], 144.8, 264.0);
  ASSERT_EQ(values.size(), 4u);
  EXPECT_DOUBLE_EQ(values[0], 1.0);  // 144.8 − 264, clipped to the range's bottom
  EXPECT_DOUBLE_EQ(values[1], 144.8 - 132.0);
  EXPECT_DOUBLE_EQ(values[2], 144.8 + 132.0);
  EXPECT_DOUBLE_EQ(values[3], 144.8 + 264.0);
}

TEST(ProbeValuesTest, ClippedValuesAreProbedOnceAndAnUnseenParameterOverItsWholeRange) {
  // 990 ± 264 and ± 132: both upper ones clip to 1000, probed once.
  EXPECT_EQ(ProbeValues(kParameters[1], 990.0, 264.0), (std::vector<double>{726.0, 858.0, 1000.0}));
  // No interval (the data do not see it): five even points of its log-scaled range, but the value's own.
  const std::vector<double> unseen = ProbeValues(kParameters[1], 1000.0, std::nan(""));
  ASSERT_EQ(unseen.size(), 4u);
  EXPECT_NEAR(unseen[0], 1.0, 1e-9);
  EXPECT_NEAR(unseen[1], std::pow(1000.0, 0.25), 1e-9);
  EXPECT_NEAR(unseen[3], std::pow(1000.0, 0.75), 1e-9);
}

TEST(OpenParameterProbeTest, TheHeldOutRunsChooseAmongValuesThatFitAsWell) {
  StickSlipEvaluator replays;
  const OpenProbeResult result = Probe().At(replays);
  ASSERT_EQ(result.open.size(), 1u);  // /A is identified: only /S is probed
  const OpenParameter& open = result.open[0];
  EXPECT_EQ(open.path, "/S");
  EXPECT_EQ(open.probed, 4);
  EXPECT_EQ(open.equivalent, 4);  // the fit run hardly sees /S
  EXPECT_DOUBLE_EQ(open.fitted, 144.8);
  EXPECT_DOUBLE_EQ(open.chosen, 144.8 + 132.0);  // the first value past the threshold
  EXPECT_NEAR(std::sqrt(open.holdout_loss_fitted), 3.3, 1e-12);
  EXPECT_NEAR(std::sqrt(open.holdout_loss), 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(result.values[0], 1.0);
  EXPECT_DOUBLE_EQ(result.values[1], open.chosen);
  EXPECT_DOUBLE_EQ(result.holdout_loss, open.holdout_loss);
  EXPECT_NEAR(std::sqrt(result.fit_loss), 0.2 + 1e-5 * open.chosen, 1e-12);
}

TEST(OpenParameterProbeTest, AValueThatFitsTheFitRunsWorseIsNeverChosen) {
  // Past 250 the fit run's error grows by 5°: 276.8 and 408.8 hold out well but are no longer the fit's equals.
  StickSlipEvaluator replays(250.0);
  const OpenProbeResult result = Probe().At(replays);
  ASSERT_EQ(result.open.size(), 1u);
  EXPECT_EQ(result.open[0].equivalent, 2);
  EXPECT_DOUBLE_EQ(result.open[0].chosen, 144.8);
  EXPECT_DOUBLE_EQ(result.values[1], 144.8);
  EXPECT_NEAR(std::sqrt(result.holdout_loss), 3.3, 1e-12);
}

TEST(OpenParameterProbeTest, IdentifiedParametersAndTheBaseOnesAreLeftAlone) {
  StickSlipEvaluator replays;
  Probe probe;
  const std::uint64_t before_identified = replays.replays_run();
  const OpenProbeResult identified = probe.At(replays, {true, true});
  EXPECT_TRUE(identified.open.empty());
  EXPECT_DOUBLE_EQ(identified.values[1], 144.8);
  EXPECT_EQ(replays.replays_run() - before_identified, 2u);  // the two losses At() computes, no probe
  // /A open but a base parameter (before first_probed = 1): only /S is probed.
  const OpenProbeResult base = probe.At(replays, {false, false}, 1);
  ASSERT_EQ(base.open.size(), 1u);
  EXPECT_EQ(base.open[0].path, "/S");
}

}  // namespace
}  // namespace orcs::identify
