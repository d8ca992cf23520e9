// Fitting model parameters to measured runs with the simulation in the loop (docs/gap.md, "How a fit works"):
// pagmo2's generational particle swarm (pso_gen) searches a box in normalised coordinates (log-scaled where a parameter is a positive scale),
// and every generation's population is one batch of replays (ReplayEvaluator: in orcs-gap, jobs through the broker), so a fit scales from two
// cores to a cluster. The objective is the mean squared (or, with Loss::kAbsolute, the mean absolute) joint-angle
// error over all fit runs and channels.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "model/identify/fit_parameter.h"
#include "model/identify/replay.h"
#include "model/identify/replay_evaluator.h"

namespace orcs::identify {

/// The replays of a set of runs, evaluated as one batch per call.
class ReplayObjective {
 public:
  /// `fixed` is applied to every replay after the model (e.g. an effect's Enabled switch); `loss` says how the
  /// angle errors are pooled.
  ReplayObjective(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs, std::vector<Override> fixed,
                  Loss loss = Loss::kSquared);

  /// The pooled loss of every point, in order: the mean squared error (deg²) or the mean absolute error (deg) over
  /// all runs, channels and rows. A point whose replay fails (unstable physics) scores kFailedPoint. `bounds`
  /// (empty, or one per point; +∞ = none): a point whose loss is sure to exceed its bound may have its replays
  /// stopped early, and then scores a lower bound of its loss that is above the bound.
  std::vector<double> Losses(const std::vector<std::vector<Override>>& points,
                             const std::vector<double>& bounds = {}) const;

  /// Per point, the residuals (simulated − measured joint angle, degrees) of every run's channels at every row after
  /// the first, in run and channel order; empty for a point whose replay failed.
  std::vector<std::vector<double>> Residuals(const std::vector<std::vector<Override>>& points) const;

  /// The residuals whose mean square is the loss, for a least-squares polish: Residuals itself for the squared
  /// loss, sign(r)·√|r| for the absolute one.
  std::vector<std::vector<double>> LossResiduals(const std::vector<std::vector<Override>>& points) const;

  Loss loss() const { return loss_; }

  static constexpr double kFailedPoint = 1e6;

 private:
  /// The error (degrees, in the loss's norm) above which `run` alone puts the pooled loss above `bound`; +∞ for no
  /// bound.
  double RunBound(double bound, const ReplayRun& run) const;

  ReplayEvaluator& replays_;
  const std::vector<ReplayRun>& runs_;
  std::vector<Override> fixed_;
  Loss loss_;
};

struct FitOptions {
  int generations = 40;   ///< generation budget of the swarm
  int population = 0;     ///< particles per generation; ≤ 0 = max(16, 8 + 6·ln(dimension))
  unsigned seed = 1;      ///< the optimiser's own generator: the same inputs give the same fit
  /// The race: asked once, after the swarm's `abandon_after`-th generation, with the best point seen so far (each
  /// parameter's value in its unit) and its objective. A reason (one line) stops the fit there, without the local
  /// stages (FitOutcome::abandoned); "" lets it go on, and the swarm runs on exactly as it would without the
  /// question. Empty = never asked. With it, a quick local look (a few Levenberg–Marquardt steps from the start)
  /// comes first, so that the question also sees the best point near the start.
  std::function<std::string(const std::vector<double>& values, double mse)> abandon;
  int abandon_after = 10;
  /// Stop a search's replays early where their point cannot beat the best it is compared with (the swarm: the
  /// particle's best; the compass search: its current point). The search is the same bit for bit, only cheaper
  /// (docs/gap.md, "How a fit works"); false runs every replay to its end.
  bool stop_replays_early = true;
  /// CMA-ES islands after the swarm (docs/gap.md, "How a fit works"; orcs-gap --islands): this many independent
  /// CMA-ES runs (pagmo's cmaes, `island_generations` generations each, different seeds) start from the swarm's
  /// last generation, concurrently; the best island's point is a second start for the local stages, and the
  /// better of the two finished fits is the result. CMA-ES adapts its search directions, so it follows the
  /// diagonal valleys a swarm and a compass search stall in. 0 = none (the default).
  int islands = 0;
  int island_generations = 150;
};

struct FitOutcome {
  std::vector<double> values;    ///< the best point found, in each parameter's unit
  double mse = 0.0;              ///< its objective (ReplayObjective::Losses: deg², or deg for the absolute loss)
  int generations = 0;           ///< swarm generations run (fewer than the budget when abandoned)
  bool abandoned = false;        ///< stopped after the swarm's first generations (FitOptions::abandon said why)
  bool abandoned_unmoved = false;  ///< abandoned while its best had not changed since the swarm's first
                                   ///< generation: its search may not have started (convergence says so)
  int evaluations = 0;           ///< points evaluated (each = one replay per run)
  bool converged = false;        ///< the local polish stopped because its step fell below 0.2 % of every
                                 ///< parameter's range, not because its budget ran out (see convergence)
  std::string convergence;       ///< why it counts as converged or not, one line
  std::string polish;            ///< what the Levenberg–Marquardt polish did, one line
  /// Per parameter: the 95 % confidence interval's half-width in its unit, NaN = not determined by the data
  /// (least_squares_polish.h).
  std::vector<double> ci95;
};

/// The assignments of `values` to `parameters`' paths.
std::vector<Override> OverridesOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values);

/// Minimises the objective over `parameters` (≥ 1): the swarm's global search (abandoned when the race says so),
/// a compass search, then a Levenberg–Marquardt polish on
/// the residuals with confidence intervals (least_squares_polish.h). Passes on what the evaluator throws (orcs-gap's: broker::BatchClientError
/// when the broker is lost).
FitOutcome Fit(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
               const FitOptions& options);

}  // namespace orcs::identify
