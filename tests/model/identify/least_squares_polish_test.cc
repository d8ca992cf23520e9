// The Levenberg–Marquardt polish and its confidence intervals on a linear system with a closed-form answer: the
// "simulation" of a run is a·sin(k/10) + b·cos(k/7) (degrees) at row k, the measured run the same at a = 1.5,
// b = −0.7 plus a fixed pseudo-noise. The least-squares solution and its covariance σ²·(XᵀX)⁻¹ are computed here
// with Eigen; the polish must find the first and report the second (widened by its AR(1) factor). A parameter the
// residuals ignore, or one that only moves with another, must be reported as not identified.
#include "model/identify/least_squares_polish.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <atomic>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace orcs::identify {
namespace {

constexpr int kRows = 400;

double Sine(int k) { return std::sin(k / 10.0); }
double Cosine(int k) { return std::cos(k / 7.0); }
double Noise(int k) { return 0.2 * std::sin(k * 12.9898 + 78.233 * std::sin(k * 0.731)); }

// Answers every replay with the columns of a·sin + (b + d)·cos, where /C changes nothing.
class LinearEvaluator : public ReplayEvaluator {
 public:
  std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
    std::vector<ReplayOutcome> outcomes;
    for (const ReplayRequest& request : requests) {
      std::map<std::string, double> values{{"/A", 0.0}, {"/B", 0.0}, {"/C", 0.0}, {"/D", 0.0}};
      for (const auto& [path, value] : request.overrides) values[path] = std::stod(value);
      std::vector<double> angles;
      for (int k = 0; k < kRows; ++k) angles.push_back(values["/A"] * Sine(k) + (values["/B"] + values["/D"]) * Cosine(k));
      ReplayOutcome outcome;
      outcome.ok = true;
      outcome.error = 0.0;
      outcome.columns.push_back({"/Sim/Rig/Motor/JointAngle", angles});
      outcomes.push_back(std::move(outcome));
    }
    replays_ += requests.size();
    return outcomes;
  }
  std::uint64_t replays_run() const override { return replays_; }

 private:
  std::atomic<std::uint64_t> replays_{0};
};

struct LinearRig {
  LinearRig() {
    measured.agent = "Rig";
    measured.motors = {"Motor"};
    std::vector<double>& angles = measured.joint_angle["Motor"];
    for (int k = 0; k < kRows; ++k) angles.push_back(1.5 * Sine(k) - 0.7 * Cosine(k) + Noise(k));
    run.name = "linear";
    run.run = &measured;
    run.channels = {"Motor"};
    run.samples = kRows - 1;
  }
  MeasuredRun measured;
  ReplayRun run;
};

TEST(LeastSquaresPolishTest, FindsTheLeastSquaresSolutionAndItsConfidenceIntervals) {
  LinearRig rig;
  LinearEvaluator evaluator;
  const std::vector<ReplayRun> runs = {rig.run};
  const ReplayObjective objective(evaluator, runs, {});
  const std::vector<FitParameter> parameters = {{"/A", "deg", -5.0, 5.0, false}, {"/B", "deg", -5.0, 5.0, false}};
  const PolishOutcome polished = PolishLeastSquares(objective, parameters, {2.0, 0.0});

  // The closed form over rows 1… (row 0 is the reset state, never compared).
  Eigen::MatrixXd x(kRows - 1, 2);
  Eigen::VectorXd y(kRows - 1);
  for (int k = 1; k < kRows; ++k) {
    x(k - 1, 0) = Sine(k);
    x(k - 1, 1) = Cosine(k);
    y(k - 1) = rig.measured.joint_angle["Motor"][static_cast<std::size_t>(k)];
  }
  const Eigen::Vector2d best = x.colPivHouseholderQr().solve(y);
  ASSERT_TRUE(polished.improved) << polished.summary;
  EXPECT_NEAR(polished.values[0], best(0), 1e-4) << polished.summary;
  EXPECT_NEAR(polished.values[1], best(1), 1e-4);
  const Eigen::VectorXd residuals = x * best - y;
  EXPECT_NEAR(polished.mse, residuals.squaredNorm() / (kRows - 1), 1e-8);

  double rho = 0.0;
  for (Eigen::Index k = 1; k < residuals.size(); ++k) rho += residuals(k) * residuals(k - 1);
  rho = std::clamp(rho / (residuals.squaredNorm()), 0.0, 0.99);  // the residuals' mean is ~0 here
  const double variance = residuals.squaredNorm() / (kRows - 1 - 2) * (1 + rho) / (1 - rho);
  const Eigen::Matrix2d covariance = variance * (x.transpose() * x).inverse();
  ASSERT_EQ(polished.ci95.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(polished.ci95[static_cast<std::size_t>(i)], 1.959964 * std::sqrt(covariance(i, i)),
                0.02 * 1.959964 * std::sqrt(covariance(i, i)))
        << i;
    EXPECT_TRUE(Identified(polished.values[static_cast<std::size_t>(i)], polished.ci95[static_cast<std::size_t>(i)]));
  }
  EXPECT_EQ(static_cast<std::uint64_t>(polished.evaluations), evaluator.replays_run());
}

// An optimum outside the box (a = 1.5 above /A's top, 1): the polish ends on the wall, within 1 % of the constrained
// optimum's error, with Ceres's projected line search and without it (steps clipped to the box), and without it in
// fewer replays.
TEST(LeastSquaresPolishTest, AnOptimumBeyondTheBoxEndsOnItsWallWithOrWithoutTheLineSearch) {
  LinearRig rig;
  Eigen::VectorXd sine(kRows - 1), cosine(kRows - 1), y(kRows - 1);
  for (int k = 1; k < kRows; ++k) {
    sine(k - 1) = Sine(k);
    cosine(k - 1) = Cosine(k);
    y(k - 1) = rig.measured.joint_angle["Motor"][static_cast<std::size_t>(k)];
  }
  const double b_at_wall = cosine.dot(y - 1.0 * sine) / cosine.squaredNorm();  // the best b with a held at 1
  const double mse_at_wall = (1.0 * sine + b_at_wall * cosine - y).squaredNorm() / (kRows - 1);
  const std::vector<ReplayRun> runs = {rig.run};
  const std::vector<FitParameter> parameters = {{"/A", "deg", -5.0, 1.0, false}, {"/B", "deg", -5.0, 5.0, false}};
  int evaluations[2] = {0, 0};
  for (const bool line_search : {true, false}) {
    LinearEvaluator evaluator;
    const ReplayObjective objective(evaluator, runs, {});
    const PolishOutcome polished =
        PolishLeastSquares(objective, parameters, {-2.0, 0.0}, {.intervals = false, .line_search = line_search});
    ASSERT_TRUE(polished.improved) << polished.summary;
    EXPECT_NEAR(polished.values[0], 1.0, 1e-4) << "line search " << line_search << ": " << polished.summary;
    // Ceres's steps along the wall are the clipped free steps, so b stops near, not at, its constrained best.
    EXPECT_NEAR(polished.values[1], b_at_wall, 0.05) << "line search " << line_search;
    EXPECT_LT(polished.mse, 1.01 * mse_at_wall) << "line search " << line_search;
    evaluations[line_search ? 0 : 1] = polished.evaluations;
  }
  EXPECT_LT(evaluations[1], evaluations[0]);
}

// The absolute loss: on a run where one row in ten is up to 40° off to one side (a snag), the least-squares fit is pulled
// towards the outliers; the polish under the absolute loss stays near the model that made the other rows, and its
// objective is the mean absolute error at its point, no higher than at the least-squares point.
TEST(LeastSquaresPolishTest, UnderTheAbsoluteLossThePolishMinimisesTheMeanAbsoluteErrorAndResistsOutliers) {
  LinearRig rig;
  std::vector<double>& angles = rig.measured.joint_angle["Motor"];
  for (std::size_t k = 5; k < angles.size(); k += 10) angles[k] += 40.0 * std::abs(Sine(static_cast<int>(k)));
  const std::vector<ReplayRun> runs = {rig.run};
  const std::vector<FitParameter> parameters = {{"/A", "deg", -5.0, 5.0, false}, {"/B", "deg", -5.0, 5.0, false}};
  const auto mean_absolute = [&](const std::vector<double>& values) {
    double sum = 0.0;
    for (int k = 1; k < kRows; ++k) {
      sum += std::abs(values[0] * Sine(k) + values[1] * Cosine(k) - angles[static_cast<std::size_t>(k)]);
    }
    return sum / (kRows - 1);
  };
  LinearEvaluator evaluator;
  const PolishOutcome squared =
      PolishLeastSquares(ReplayObjective(evaluator, runs, {}, Loss::kSquared), parameters, {0.0, 0.0});
  const PolishOutcome absolute = PolishLeastSquares(ReplayObjective(evaluator, runs, {}, Loss::kAbsolute), parameters,
                                                    {0.0, 0.0}, {.iterations = 50});
  ASSERT_TRUE(squared.improved && absolute.improved) << absolute.summary;
  EXPECT_NEAR(absolute.mse, mean_absolute(absolute.values), 1e-9);
  EXPECT_LT(absolute.mse, mean_absolute(squared.values));
  EXPECT_GT(std::abs(squared.values[0] - 1.5), 0.2) << "the outliers pull the least-squares fit";
  EXPECT_LT(std::abs(absolute.values[0] - 1.5), 0.1) << absolute.values[0];
  EXPECT_LT(std::abs(absolute.values[1] + 0.7), 0.1) << absolute.values[1];
}

TEST(LeastSquaresPolishTest, AParameterTheDataDoNotSeeIsNotIdentified) {
  LinearRig rig;
  LinearEvaluator evaluator;
  const std::vector<ReplayRun> runs = {rig.run};
  const ReplayObjective objective(evaluator, runs, {});
  // /C changes nothing; /D only ever adds to /B, so B and D are determined only as a sum.
  const std::vector<FitParameter> parameters = {{"/A", "deg", -5.0, 5.0, false},
                                                {"/B", "deg", -5.0, 5.0, false},
                                                {"/C", "deg", 0.1, 10.0, true},
                                                {"/D", "deg", -5.0, 5.0, false}};
  const PolishOutcome polished = PolishLeastSquares(objective, parameters, {1.0, 0.5, 1.0, 0.5});
  ASSERT_EQ(polished.ci95.size(), 4u);
  EXPECT_TRUE(Identified(polished.values[0], polished.ci95[0])) << polished.ci95[0];
  EXPECT_FALSE(Identified(polished.values[1], polished.ci95[1])) << polished.ci95[1];
  EXPECT_FALSE(Identified(polished.values[2], polished.ci95[2])) << polished.ci95[2];
  EXPECT_FALSE(Identified(polished.values[3], polished.ci95[3])) << polished.ci95[3];
  EXPECT_NEAR(polished.values[1] + polished.values[3], -0.7, 0.05) << "the sum is determined";
}

TEST(LeastSquaresPolishTest, AFailedStartIsReportedNotPolished) {
  LinearRig rig;
  rig.run.channels = {"Elsewhere"};  // no such column in the replays: every point fails
  rig.measured.joint_angle["Elsewhere"] = rig.measured.joint_angle["Motor"];
  LinearEvaluator evaluator;
  const std::vector<ReplayRun> runs = {rig.run};
  const ReplayObjective objective(evaluator, runs, {});
  const PolishOutcome polished = PolishLeastSquares(objective, {{"/A", "deg", -5.0, 5.0, false}}, {2.0});
  EXPECT_FALSE(polished.improved);
  EXPECT_EQ(polished.values, std::vector<double>{2.0});
  EXPECT_EQ(polished.mse, ReplayObjective::kFailedPoint);
  EXPECT_NE(polished.summary.find("not polished"), std::string::npos) << polished.summary;
}

}  // namespace
}  // namespace orcs::identify
