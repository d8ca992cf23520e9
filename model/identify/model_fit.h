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
#include "model/identify/replay_objective.h"

namespace orcs::identify {

/// A point the caller offers as a start for the local stages (the scan's best distinct points): each parameter's
/// value in its unit, and its objective.
struct FitStart {
  std::vector<double> values;
  double mse = 0.0;
};

struct FitOptions {
  int generations = 40;   ///< generation budget of the swarm
  int population = 0;     ///< particles per generation; ≤ 0 = max(16, 8 + 6·ln(dimension))
  unsigned seed = 1;      ///< the optimiser's own generator: the same inputs give the same fit
  /// The race: after the swarm's `abandon_after`-th generation a Levenberg–Marquardt polish runs from the best point
  /// seen so far (and the compass search after it, unless it converged), and the question is asked once, of the
  /// polished point (each parameter's value in its unit) and its objective. A reason (one line) stops the fit there with that
  /// point (FitOutcome::abandoned) — but never an unconverged one: then, as on "", the swarm runs on exactly as it
  /// would without the question, and the polished point is one more start for the local stages. Empty = never asked.
  std::function<std::string(const std::vector<double>& values, double mse)> abandon;
  int abandon_after = 10;
  /// Stop a search's replays early where their point cannot beat the best it is compared with (the swarm: the
  /// particle's best; the compass search: its current point). The search is the same bit for bit, only cheaper
  /// (docs/gap.md, "How a fit works"); false runs every replay to its end.
  bool stop_replays_early = true;
  /// Other starts for the local stages (the scan's best distinct points), beside the swarm's particles.
  std::vector<FitStart> starts;
  /// The local stages run from this many of the best mutually distinct points of the swarm's particles and
  /// `starts` (docs/gap.md, "How a fit works"), at once; the best finished fit is the result. A single local
  /// search from the swarm's best stopped in local minima (a 1.5° backlash fitted as 1.19°).
  int local_starts = 3;
  /// Of the local stages' results within 1 % of the best, keep the one that moved least from the parameters'
  /// starts (docs/gap.md, "How a fit works"): for a fit whose starts are a model's own values (orcs-gap's refit),
  /// where minima that fit alike are told apart by the smaller change. An effect's fit starts where its scan
  /// pointed, which means nothing: there the best is kept (a LuGre friction's soft-bristle minimum fits as well
  /// as its true one and holds out far worse).
  bool least_change = false;
  /// CMA-ES islands after the swarm (docs/gap.md, "How a fit works"; orcs-gap --islands): this many independent
  /// CMA-ES runs (pagmo's cmaes, `island_generations` generations each, different seeds) start from the swarm's
  /// last generation, concurrently; the best island's point is one more start for the local stages. CMA-ES adapts
  /// its search directions, so it follows the diagonal valleys a swarm and a compass search stall in. 0 = none
  /// (the default).
  int islands = 0;
  int island_generations = 150;
};

/// Where a fitted parameter ended against its search range (FitOutcome::bounds).
enum class BoundState {
  kInside,       ///< inside the range
  kBeyond,       ///< at the catalogue's bound, re-searched beyond it, and ended outside the catalogue's range
  kAtLower,      ///< at the bottom of its (possibly widened) range: the data want less than the search allows
  kAtUpper,      ///< at the top, likewise
};

struct FitOutcome {
  std::vector<double> values;    ///< the best point found, in each parameter's unit
  double mse = 0.0;              ///< its objective (ReplayObjective::Losses: deg², or deg for the absolute loss)
  int generations = 0;           ///< swarm generations run (fewer than the budget when abandoned)
  bool abandoned = false;        ///< stopped after the swarm's first generations (FitOptions::abandon said why)
  int evaluations = 0;           ///< points evaluated (each = one replay per run)
  bool converged = false;        ///< the best local search stopped because its step fell below 0.2 % of every
                                 ///< parameter's range, not because its budget ran out (see convergence)
  std::string convergence;       ///< why it counts as converged or not, one line
  std::string polish;            ///< what the Levenberg–Marquardt polish did, one line
  int local_starts = 0;          ///< local searches run (FitOptions::local_starts, the race's and the re-search's)
  /// Per parameter: where it ended against its range. A parameter at a bound whose range could widen (a log-scaled
  /// one) was re-searched beyond it first; one still at a bound is reported (kAtLower/kAtUpper).
  std::vector<BoundState> bounds;
  /// Per parameter: the 95 % confidence interval's half-width in its unit, NaN = not determined by the data
  /// (least_squares_polish.h).
  std::vector<double> ci95;
};
/// Minimises the objective over `parameters` (≥ 1): the swarm's global search (abandoned when the race says so,
/// after its best point has converged), then the local stages — a compass search and a Levenberg–Marquardt polish on
/// the residuals — from several of the best distinct points at once; a parameter that ends at a bound is
/// re-searched beyond it where its range can widen; the confidence intervals of the best (least_squares_polish.h).
/// Passes on what the evaluator throws (orcs-gap's: runtime::BatchClientError when the broker is lost).
FitOutcome Fit(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
               const FitOptions& options);

}  // namespace orcs::identify
