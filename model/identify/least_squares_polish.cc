#include "model/identify/least_squares_polish.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "model/identify/gap_statistics.h"

namespace orcs::identify {
namespace {

// Forward-difference steps in the normalised box: 0.1 % of a parameter's (log-)range for the polish's Jacobians,
// 1 % for the intervals' — a parameter whose effect shows in whole simulation steps (a backlash's width: the gap is
// crossed a step earlier or later) changes no residual over 0.1 % and would look undetermined.
constexpr double kDifferenceStep = 1e-3;
constexpr double kIntervalDifferenceStep = 1e-2;
// z of a two-sided 95 % interval.
constexpr double kZ95 = 1.959964;

std::vector<double> ValuesAt(const std::vector<FitParameter>& parameters, const double* unit) {
  std::vector<double> values;
  for (std::size_t i = 0; i < parameters.size(); ++i) values.push_back(FromUnit(parameters[i], unit[i]));
  return values;
}

// The point itself and, for the Jacobian, one point per parameter moved by the difference step (backwards at the
// top of the box). Returns the steps taken.
std::vector<double> DifferencePoints(const std::vector<FitParameter>& parameters, const double* unit,
                                     std::vector<std::vector<Override>>& points, double step = kDifferenceStep) {
  const std::size_t n = parameters.size();
  std::vector<double> steps(n);
  points.push_back(OverridesOf(parameters, ValuesAt(parameters, unit)));
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> moved(unit, unit + n);
    steps[i] = moved[i] + step <= 1.0 ? step : -step;
    moved[i] += steps[i];
    points.push_back(OverridesOf(parameters, ValuesAt(parameters, moved.data())));
  }
  return steps;
}

// Residuals and their Jacobian in the normalised box, each Jacobian one batch of n + 1 replays per run.
class ReplayResiduals : public ceres::CostFunction {
 public:
  ReplayResiduals(const ReplayObjective& objective, const std::vector<FitParameter>& parameters, int residuals,
                  int& evaluations)
      : objective_(objective), parameters_(parameters), evaluations_(evaluations) {
    set_num_residuals(residuals);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(parameters.size()));
  }

  bool Evaluate(double const* const* unit, double* residuals, double** jacobians) const override {
    const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    std::vector<std::vector<Override>> points;
    std::vector<double> steps;
    if (jacobian) {
      steps = DifferencePoints(parameters_, unit[0], points);
    } else {
      points.push_back(OverridesOf(parameters_, ValuesAt(parameters_, unit[0])));
    }
    const std::vector<std::vector<double>> all = objective_.LossResiduals(points);
    evaluations_ += static_cast<int>(points.size());
    const auto m = static_cast<std::size_t>(num_residuals());
    for (const std::vector<double>& r : all) {
      if (r.size() != m) return false;  // a failed replay: Ceres shrinks its step
    }
    std::copy(all[0].begin(), all[0].end(), residuals);
    if (!jacobian) return true;
    const std::size_t n = parameters_.size();
    for (std::size_t row = 0; row < m; ++row) {
      for (std::size_t i = 0; i < n; ++i) jacobians[0][row * n + i] = (all[i + 1][row] - all[0][row]) / steps[i];
    }
    return true;
  }

 private:
  const ReplayObjective& objective_;
  const std::vector<FitParameter>& parameters_;
  int& evaluations_;
};

double MeanSquare(const std::vector<double>& r) {
  double sum = 0.0;
  for (double v : r) sum += v * v;
  return r.empty() ? std::numeric_limits<double>::infinity() : sum / static_cast<double>(r.size());
}

// The 95 % half-widths at `unit` from one Jacobian batch, in each parameter's unit; NaN where the Jacobian is
// singular in that parameter's direction.
std::vector<double> IntervalsAt(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                const std::vector<double>& unit, int& evaluations) {
  const std::size_t n = parameters.size();
  std::vector<double> ci(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<std::vector<Override>> points;
  const std::vector<double> steps = DifferencePoints(parameters, unit.data(), points, kIntervalDifferenceStep);
  const std::vector<std::vector<double>> all = objective.Residuals(points);
  evaluations += static_cast<int>(points.size());
  const std::size_t m = all[0].size();
  if (m <= n || std::any_of(all.begin(), all.end(), [m](const auto& r) { return r.size() != m; })) return ci;
  // The Jacobian in each parameter's own unit: d(residual)/d(value) = d/du · du/d(value).
  Eigen::MatrixXd jacobian(m, n);
  const std::vector<double> values = ValuesAt(parameters, unit.data());
  for (std::size_t i = 0; i < n; ++i) {
    const FitParameter& p = parameters[i];
    const double du_dvalue = p.log_scale ? 1.0 / (values[i] * (std::log(p.upper) - std::log(p.lower)))
                                         : 1.0 / (p.upper - p.lower);
    for (std::size_t row = 0; row < m; ++row) {
      jacobian(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(i)) =
          (all[i + 1][row] - all[0][row]) / steps[i] * du_dvalue;
    }
  }
  const double rho = Lag1Correlation(all[0]);
  const double variance = MeanSquare(all[0]) * static_cast<double>(m) / static_cast<double>(m - n) *
                          (1.0 + rho) / (1.0 - rho);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const double cutoff = sigma(0) * 1e-8;
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0.0;
    bool singular = false;
    for (Eigen::Index k = 0; k < sigma.size(); ++k) {
      const double v = svd.matrixV()(static_cast<Eigen::Index>(i), k);
      if (sigma(k) <= cutoff) {
        singular = singular || std::abs(v) > 1e-3;  // the parameter moves along a direction the data do not see
        continue;
      }
      sum += v * v / (sigma(k) * sigma(k));
    }
    if (!singular) ci[i] = kZ95 * std::sqrt(variance * sum);
  }
  return ci;
}

}  // namespace

std::vector<double> ConfidenceIntervals(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                        const std::vector<double>& values, int& evaluations) {
  std::vector<double> unit;
  for (std::size_t i = 0; i < parameters.size(); ++i) unit.push_back(ToUnit(parameters[i], values[i]));
  return IntervalsAt(objective, parameters, unit, evaluations);
}

bool Identified(double value, double ci95) { return std::isfinite(ci95) && ci95 < std::abs(value); }

PolishOutcome PolishLeastSquares(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                 const std::vector<double>& start, const PolishOptions& polish) {
  PolishOutcome outcome;
  outcome.values = start;
  std::vector<double> unit;
  for (std::size_t i = 0; i < parameters.size(); ++i) unit.push_back(ToUnit(parameters[i], start[i]));
  const std::vector<std::vector<double>> first = objective.LossResiduals({OverridesOf(parameters, start)});
  outcome.evaluations = 1;
  outcome.mse = first[0].empty() ? ReplayObjective::kFailedPoint : MeanSquare(first[0]);
  if (first[0].empty()) {
    outcome.summary = "not polished: the start's replay failed";
    outcome.ci95.assign(parameters.size(), std::numeric_limits<double>::quiet_NaN());
    return outcome;
  }

  ceres::Problem problem;
  std::vector<double> polished = unit;
  problem.AddResidualBlock(
      new ReplayResiduals(objective, parameters, static_cast<int>(first[0].size()), outcome.evaluations), nullptr,
      polished.data());
  for (int i = 0; i < static_cast<int>(parameters.size()); ++i) {
    problem.SetParameterLowerBound(polished.data(), i, 0.0);
    problem.SetParameterUpperBound(polished.data(), i, 1.0);
  }
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = polish.iterations;
  options.logging_type = ceres::SILENT;
  // Without the line search, a step that leaves the box is clipped to it.
  if (!polish.line_search) options.max_num_line_search_step_size_iterations = 0;
  options.num_threads = 1;  // the parallelism is the batch of replays behind each Jacobian
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  const double polished_mse = 2.0 * summary.final_cost / static_cast<double>(first[0].size());
  outcome.converged = summary.termination_type == ceres::CONVERGENCE;
  outcome.summary = "Levenberg–Marquardt: " + std::to_string(summary.iterations.size()) + " iterations, " +
                    (summary.termination_type == ceres::CONVERGENCE ? "converged" : "stopped") + " (" +
                    summary.message + ")";
  if (summary.IsSolutionUsable() && polished_mse < outcome.mse) {
    outcome.values = ValuesAt(parameters, polished.data());
    outcome.mse = polished_mse;
    outcome.improved = true;
    unit = polished;
  }
  outcome.ci95 = polish.intervals ? IntervalsAt(objective, parameters, unit, outcome.evaluations)
                           : std::vector<double>(parameters.size(), std::numeric_limits<double>::quiet_NaN());
  return outcome;
}

}  // namespace orcs::identify
