// The last stage of a fit (docs/gap.md, "How a fit works"): Levenberg–Marquardt on the replay residuals (Ceres;
// for the absolute loss, residuals whose squares are the absolute errors),
// from the point the global search ended at, and the parameters' 95 % confidence intervals from the Jacobian
// there — which tell the report what the data cannot identify. Every Jacobian is one batch of replays (forward
// differences, one point per parameter), so it runs on all workers at once like a generation of the swarm.
#pragma once

#include <string>
#include <vector>

#include "model/identify/fit_parameter.h"
#include "model/identify/replay_objective.h"

namespace orcs::identify {

struct PolishOutcome {
  std::vector<double> values;  ///< the polished point, in each parameter's unit (the start when nothing improved)
  double mse = 0.0;            ///< its objective (ReplayObjective::Losses: deg², or deg for the absolute loss)
  int evaluations = 0;         ///< points replayed
  bool improved = false;       ///< the polish lowered the objective
  bool converged = false;      ///< Ceres met its tolerance (function, gradient or step), not its iteration bound
  std::string summary;         ///< Ceres's termination, one line
  /// Per parameter: the half-width of its 95 % confidence interval, in its unit, NaN when the data do not
  /// determine it (a singular Jacobian direction). From σ²·(JᵀJ)⁻¹ with σ² the residuals' variance, widened for
  /// their correlation from step to step (an AR(1) estimate: successive rows of a replay are not independent).
  /// Always from the angle residuals themselves: with the absolute loss, the least-squares interval at the
  /// absolute loss's optimum (an approximation, docs/gap.md).
  std::vector<double> ci95;
};

struct PolishOptions {
  int iterations = 15;  ///< bound on Ceres's iterations (successful and unsuccessful steps)
  /// Whether to compute the confidence intervals at the end (one more Jacobian); without, ci95 is all NaN (the
  /// local searches of a multi-start fit and the relaxed scan need none: the fit computes them once, for its best).
  bool intervals = true;
  /// Ceres's projected line search where a step leaves the box. Each of its steps costs a Jacobian, but it is what
  /// takes a fit to a hidden Stribeck friction's values; quick relaxations do without it.
  bool line_search = true;
};

/// Polishes `start` (one value per parameter, in its unit).
PolishOutcome PolishLeastSquares(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                 const std::vector<double>& start, const PolishOptions& polish = {});

/// The 95 % half-widths at `values` (one per parameter, in its unit; NaN where the data do not determine it), as
/// PolishOutcome::ci95: one Jacobian batch. Adds the replays it ran to `evaluations`.
std::vector<double> ConfidenceIntervals(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                        const std::vector<double>& values, int& evaluations);

/// Whether a fitted value is determined by the data: its interval is finite and narrower than the value itself.
bool Identified(double value, double ci95);

}  // namespace orcs::identify
