#include "model/identify/model_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <pagmo/algorithm.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/compass_search.hpp>
#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/batch_evaluators/member_bfe.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include "base/demand.h"
#include "model/identify/batch_problem.h"
#include "model/identify/least_squares_polish.h"
#include "model/core/text.h"

namespace orcs::identify {
namespace {

std::vector<double> Values(const std::vector<FitParameter>& parameters, const double* unit) {
  std::vector<double> values;
  for (std::size_t i = 0; i < parameters.size(); ++i) values.push_back(FromUnit(parameters[i], unit[i]));
  return values;
}

pagmo::vector_double UnitOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  pagmo::vector_double unit;
  for (std::size_t i = 0; i < parameters.size(); ++i) unit.push_back(ToUnit(parameters[i], values[i]));
  return unit;
}

// What one search's evaluations have seen: the best point, and how many batches the swarm has sent. Shared by the
// problem's evaluator and whoever runs the search; every search (the swarm, each local search) has its own.
struct FitWatch {
  const FitOptions* options = nullptr;
  const std::vector<FitParameter>* parameters = nullptr;
  pagmo::vector_double best_x;                             // the best point evaluated so far (unit box)
  double best_f = std::numeric_limits<double>::infinity();  // its objective, deg²
  std::uint64_t evaluated = 0;                             // points evaluated through the problem
  int swarm_batches = -1;                                  // generations of the swarm so far; −1: not a swarm
  // Early stops (FitOptions::stop_replays_early): per point, the objective above which its value no longer matters.
  std::vector<double> particle_best;             // the swarm: each particle's best so far, as pso_gen keeps it
  std::map<pagmo::vector_double, double> bounds;  // the swarm batch being evaluated: point → its particle's best
  bool in_compass = false;                        // the compass search is running
  double compass_best = std::numeric_limits<double>::infinity();  // its current point's objective (or above it)

  // The bound of point x: past it, the search that asked for x ignores x's value.
  double BoundOf(const pagmo::vector_double& x) const {
    const auto found = bounds.find(x);
    if (found != bounds.end()) return found->second;
    return in_compass ? compass_best : std::numeric_limits<double>::infinity();
  }
};

// pagmo's batch evaluator for the swarm: member_bfe's work (the problem's batch_fitness: the generation as one batch),
// plus each particle's best so far as its new point's bound. pso_gen uses a particle's new objective for one thing
// only, to ask whether it is at or below the particle's best (pso_gen.cpp, "update the particles memory"); its
// batch lists the particles in order. So a replay that stops once its point is sure to lose that comparison, and
// answers with a lower bound above the best, leaves the swarm's path exactly as it would be.
struct SwarmBatch {
  std::shared_ptr<FitWatch> watch;

  pagmo::vector_double operator()(const pagmo::problem& problem, const pagmo::vector_double& xs) const {
    FitWatch& w = *watch;
    const std::size_t n = problem.get_nx();
    ORCS_DEMAND_MSG(xs.size() == w.particle_best.size() * n, "the swarm's batch is one point per particle");
    for (std::size_t p = 0; p < w.particle_best.size(); ++p) {
      const auto first = xs.begin() + static_cast<std::ptrdiff_t>(p * n);
      const auto [entry, added] = w.bounds.emplace(pagmo::vector_double(first, first + static_cast<std::ptrdiff_t>(n)),
                                                   w.particle_best[p]);
      // Two particles on one point: the looser bound serves both.
      if (!added) entry->second = std::max(entry->second, w.particle_best[p]);
    }
    pagmo::vector_double objectives;
    try {
      objectives = pagmo::member_bfe{}(problem, xs);
    } catch (...) {
      w.bounds.clear();
      throw;
    }
    w.bounds.clear();
    for (std::size_t p = 0; p < w.particle_best.size(); ++p) {
      w.particle_best[p] = std::min(w.particle_best[p], objectives[p]);
    }
    return objectives;
  }
};

// The pagmo problem: evolve's unit-box BatchProblem, whose cache evaluates what pagmo asks for as one batch of
// replays (member_bfe calls batch_fitness; every generation is one call). `after_batch` is told after each batch
// (the swarm's race); it may throw to stop the search.
pagmo::problem ReplayProblem(const ReplayObjective& objective, const std::shared_ptr<FitWatch>& watch,
                             std::function<void()> after_batch = {}) {
  auto cache = std::make_shared<GenerationCache>();
  cache->evaluate = [&objective, watch, after_batch](const std::vector<pagmo::vector_double>& xs) {
    const std::vector<FitParameter>& parameters = *watch->parameters;
    std::vector<std::vector<Override>> points;
    for (const pagmo::vector_double& x : xs) points.push_back(OverridesOf(parameters, Values(parameters, x.data())));
    std::vector<double> bounds;
    if (watch->options->stop_replays_early) {
      for (const pagmo::vector_double& x : xs) bounds.push_back(watch->BoundOf(x));
    }
    const std::vector<double> errors = objective.Losses(points, bounds);
    watch->evaluated += xs.size();
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (errors[i] < watch->best_f) std::tie(watch->best_x, watch->best_f) = std::tie(xs[i], errors[i]);
      if (watch->in_compass) watch->compass_best = std::min(watch->compass_best, errors[i]);
    }
    if (watch->swarm_batches >= 0) ++watch->swarm_batches;
    if (after_batch) after_batch();
    return errors;
  };
  return pagmo::problem{BatchProblem(watch->parameters->size(), std::move(cache))};
}

// The local search stops when its step has shrunk below kPolishStop of the (normalised) range, or after its budget.
constexpr double kPolishStart = 0.05;
constexpr double kPolishStop = 0.002;
constexpr unsigned kPolishBudgetPerDimension = 40;
// The CMA-ES islands' first step, as a share of the unit box: wide enough to leave the swarm's basin.
constexpr double kIslandStep = 0.3;
// Two starts of the local stages are distinct when they differ by at least this share of some parameter's range.
constexpr double kDistinctStarts = 0.05;
// A parameter within this share of its range from a bound is at the bound.
constexpr double kAtBound = 0.005;
// A log-scaled parameter at a bound is re-searched in a range this many times wider on that side.
constexpr double kWidening = 4.0;
// Local minima whose objectives are within this share of the best fit the runs alike (LeastChangeOfTheBest).
constexpr double kNearTie = 0.01;

// The local stages from one start: a compass search until its step is small (the convergence test), then
// Levenberg–Marquardt on the residuals, without the confidence intervals (Fit computes those once, for its best).
// Each local search has its own problem and watch, so that several run at once.
FitOutcome LocalStages(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                       const FitOptions& options, const pagmo::vector_double& start_x, double start_f) {
  auto watch = std::make_shared<FitWatch>();
  watch->options = &options;
  watch->parameters = &parameters;
  const pagmo::problem problem = ReplayProblem(objective, watch);
  pagmo::population polish(problem, 0u, options.seed);
  polish.push_back(start_x, {start_f});
  const unsigned budget = kPolishBudgetPerDimension * static_cast<unsigned>(parameters.size());
  // pagmo's compass search moves only to a trial point strictly better than its current one, so a trial's value
  // matters only below the current point's: that is its bound.
  watch->in_compass = true;
  watch->compass_best = start_f;
  polish = pagmo::algorithm{pagmo::compass_search(budget, kPolishStart, kPolishStop, 0.5)}.evolve(polish);
  // Its budget counts the points it asks for; a point asked for twice is cached.
  const auto polish_evaluations = polish.get_problem().get_fevals();

  const PolishOutcome squares = PolishLeastSquares(objective, parameters, Values(parameters, polish.champion_x().data()),
                                                   {.intervals = false});
  FitOutcome outcome;
  outcome.values = squares.values;
  outcome.mse = std::min(squares.mse, polish.champion_f()[0]);
  outcome.polish = squares.summary;
  outcome.evaluations = static_cast<int>(watch->evaluated) + squares.evaluations;
  outcome.local_starts = 1;
  outcome.converged = polish_evaluations < budget;
  outcome.convergence =
      outcome.converged
          ? "converged: the local search's step fell below " + text::FormatDouble(kPolishStop * 100.0) +
                " % of every parameter's range after " + std::to_string(polish_evaluations) + " evaluations"
          : "did not converge: the local search used its whole budget of " + std::to_string(budget) +
                " evaluations with its step still above " + text::FormatDouble(kPolishStop * 100.0) + " % of the range";
  return outcome;
}

// A polish that improves its start by less than this share has stalled where it is: as converged as it gets. A
// Levenberg–Marquardt polish bounded to the box often ends without meeting Ceres's tolerance where a parameter
// presses on a bound (an effect fading at the end of its range); a 1 % change could not turn the race's answer.
constexpr double kStalled = 0.01;

// A Levenberg–Marquardt polish from one start, on its own (the local stages' first step from every start, the race's
// convergence before it may abandon a fit, the re-search beyond a bound): converged when Ceres met its tolerance or
// the polish stalled (improved its start by less than kStalled).
FitOutcome Polish(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                  const pagmo::vector_double& start_x, double start_f) {
  const PolishOutcome polished =
      PolishLeastSquares(objective, parameters, Values(parameters, start_x.data()), {.intervals = false});
  FitOutcome outcome;
  outcome.values = Values(parameters, start_x.data());
  outcome.mse = start_f;
  if (polished.mse < start_f) std::tie(outcome.values, outcome.mse) = std::tie(polished.values, polished.mse);
  outcome.polish = polished.summary;
  outcome.evaluations = polished.evaluations;
  outcome.local_starts = 1;
  // A polish that could not run (its start's replay failed or gave no residuals) has not stalled: it never moved.
  const bool stalled = polished.evaluations > 1 && !(start_f - outcome.mse > kStalled * start_f);
  outcome.converged = polished.converged || stalled;
  outcome.convergence = polished.converged ? "converged: Levenberg–Marquardt met its tolerance"
                        : stalled          ? "converged: a Levenberg–Marquardt polish improved it by less than 1 %"
                                           : "did not converge: " + polished.summary;
  return outcome;
}

// A start of the local stages: a point of the unit box and its objective.
struct Start {
  pagmo::vector_double x;
  double f = 0.0;
};

bool Distinct(const pagmo::vector_double& a, const pagmo::vector_double& b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::abs(a[i] - b[i]) >= kDistinctStarts) return true;
  }
  return false;
}

// Adds to `chosen` the best points of `pool` distinct from every chosen one, until it holds `count`.
void AddBestDistinct(std::vector<Start> pool, std::size_t count, std::vector<Start>& chosen) {
  std::stable_sort(pool.begin(), pool.end(), [](const Start& a, const Start& b) { return a.f < b.f; });
  for (const Start& start : pool) {
    if (chosen.size() >= count) break;
    if (!std::isfinite(start.f)) continue;
    const bool distinct = std::all_of(chosen.begin(), chosen.end(), [&](const Start& c) { return Distinct(c.x, start.x); });
    if (distinct) chosen.push_back(start);
  }
}

// The starts of the local stages: the swarm's best point, the best of the other sources (the scan, the islands)
// distinct from it — each source's best gets its own search, since a basin the swarm left is often the scan's —
// then the best distinct points of all until there are `count`.
std::vector<Start> ChooseStarts(const std::vector<Start>& swarm, const std::vector<std::vector<Start>>& others,
                                int count) {
  std::vector<Start> chosen;
  AddBestDistinct(swarm, 1, chosen);
  std::vector<Start> all = swarm;
  for (const std::vector<Start>& source : others) {
    AddBestDistinct(source, chosen.size() + 1, chosen);
    all.insert(all.end(), source.begin(), source.end());
  }
  AddBestDistinct(std::move(all), static_cast<std::size_t>(std::max(count, 1)), chosen);
  return chosen;
}

// The polishes from every start at once (their replays share the workers); the finished polishes in start order.
std::vector<FitOutcome> PolishFrom(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                   const std::vector<Start>& starts) {
  std::vector<std::future<FitOutcome>> searches;
  for (const Start& start : starts) {
    searches.push_back(std::async(std::launch::async, [&objective, &parameters, &start] {
      return Polish(objective, parameters, start.x, start.f);
    }));
  }
  std::vector<FitOutcome> outcomes;
  for (auto& search : searches) outcomes.push_back(search.get());
  return outcomes;
}

// The local stages from every start at once (their replays share the workers); the finished searches in start order.
std::vector<FitOutcome> LocalStagesFrom(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                        const FitOptions& options, const std::vector<Start>& starts) {
  std::vector<std::future<FitOutcome>> searches;
  for (const Start& start : starts) {
    searches.push_back(std::async(std::launch::async, [&objective, &parameters, &options, &start] {
      FitOutcome outcome = LocalStages(objective, parameters, options, start.x, start.f);
      if (!(outcome.mse <= start.f)) {  // the compass search and the polish only move to better points
        outcome.values = Values(parameters, start.x.data());
        outcome.mse = start.f;
      }
      return outcome;
    }));
  }
  std::vector<FitOutcome> outcomes;
  for (auto& search : searches) outcomes.push_back(search.get());
  return outcomes;
}

// One of several finished fits, with every fit's replays and local searches counted.
FitOutcome Chosen(std::vector<FitOutcome> fits, std::size_t chosen) {
  ORCS_DEMAND(chosen < fits.size());
  int evaluations = 0;
  int local_starts = 0;
  for (const FitOutcome& fit : fits) {
    evaluations += fit.evaluations;
    local_starts += fit.local_starts;
  }
  FitOutcome outcome = std::move(fits[chosen]);
  outcome.evaluations = evaluations;
  outcome.local_starts = local_starts;
  return outcome;
}

// The best of several finished fits (the first of equals).
FitOutcome BestOf(std::vector<FitOutcome> fits) {
  ORCS_DEMAND(!fits.empty());
  std::size_t best = 0;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    if (fits[i].mse < fits[best].mse) best = i;
  }
  return Chosen(std::move(fits), best);
}

// With FitOptions::least_change: of the finished local searches within kNearTie of the best, the one that moved
// least from where the fit started (the model's values, for orcs-gap's refit). Such minima fit the runs alike to well within
// what the runs can tell (a mean error known to a few per cent), and the data then ask for the smaller change: the
// XL330 fitted on its kp400 runs has two minima 0.6 % apart, one keeping a Coulomb friction of 0.005 N·m near the
// model's, the other dropping it to its bound, and only the first carries over to kp100 (24.9 against 27.1 mrad).
FitOutcome LeastChangeOfTheBest(std::vector<FitOutcome> fits, const std::vector<FitParameter>& parameters) {
  ORCS_DEMAND(!fits.empty());
  double best_mse = std::numeric_limits<double>::infinity();
  for (const FitOutcome& fit : fits) best_mse = std::min(best_mse, fit.mse);
  pagmo::vector_double start;
  for (const FitParameter& p : parameters) start.push_back(ToUnit(p, p.start));
  const auto change = [&](const FitOutcome& fit) {
    const pagmo::vector_double x = UnitOf(parameters, fit.values);
    double sum = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) sum += (x[i] - start[i]) * (x[i] - start[i]);
    return sum;
  };
  std::size_t chosen = fits.size();
  for (std::size_t i = 0; i < fits.size(); ++i) {
    if (!(fits[i].mse <= best_mse * (1.0 + kNearTie))) continue;
    if (chosen == fits.size() || change(fits[i]) < change(fits[chosen])) chosen = i;
  }
  if (chosen == fits.size()) return BestOf(std::move(fits));  // no finite objective: the first of equals
  return Chosen(std::move(fits), chosen);
}

// The local stages of a fit (FitOptions::least_change off): a polish from each start at once, then the compass
// search and a last polish from the best of them. One compass search per fit: on the A-Series a compass search
// from every start took the example's diagnosis from 117 s to 214 s.
FitOutcome LocalStagesFromTheBestPolish(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                        const FitOptions& options, const std::vector<Start>& starts,
                                        std::optional<FitOutcome>& rescued) {
  std::vector<FitOutcome> polished = PolishFrom(objective, parameters, starts);
  if (rescued) polished.push_back(std::move(*rescued));
  const FitOutcome best = BestOf(std::move(polished));
  FitOutcome outcome = LocalStages(objective, parameters, options, UnitOf(parameters, best.values), best.mse);
  if (!(outcome.mse <= best.mse)) {  // the compass search and polish only move to better points; keep the best seen
    outcome.values = best.values;
    outcome.mse = best.mse;
  }
  outcome.evaluations += best.evaluations;
  outcome.local_starts = best.local_starts;
  return outcome;
}

// The local stages of a fit with FitOptions::least_change: the compass search and a polish from every start, so
// that each start's own minimum is known (a polish alone can slide from the start into the neighbouring basin),
// then the least change of those that fit alike.
FitOutcome LeastChangeOfTheLocalStages(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                                       const FitOptions& options, const std::vector<Start>& starts,
                                       std::optional<FitOutcome>& rescued) {
  std::vector<FitOutcome> searched = LocalStagesFrom(objective, parameters, options, starts);
  if (rescued) searched.push_back(std::move(*rescued));
  return LeastChangeOfTheBest(std::move(searched), parameters);
}

// Where each value sits against its parameter's range.
std::vector<BoundState> BoundsOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::vector<BoundState> bounds;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const double u = ToUnit(parameters[i], values[i]);
    bounds.push_back(u <= kAtBound ? BoundState::kAtLower : u >= 1.0 - kAtBound ? BoundState::kAtUpper
                                                                                 : BoundState::kInside);
  }
  return bounds;
}

// A fit whose best point has a parameter at a bound of its range: such a point is often a local minimum that a
// wider range would let go on (a Stribeck friction's breakaway torque at the top of its range, its velocity a tenth
// of the truth). Each log-scaled parameter at a bound has its range widened kWidening times on that side, and a
// Levenberg–Marquardt polish runs again from the point; the better fit is kept. What is still at a bound of its (widened) range
// is reported; a parameter that moved past the catalogue's range is reported as beyond it. `ranges` comes in as
// the fit's parameters and goes out as the ranges the result belongs to.
FitOutcome ReSearchBeyondBounds(const ReplayObjective& objective, std::vector<FitParameter>& ranges, FitOutcome fit) {
  const std::vector<FitParameter> catalogue = ranges;
  fit.bounds = BoundsOf(catalogue, fit.values);
  std::vector<FitParameter> widened = catalogue;
  bool widen = false;
  for (std::size_t i = 0; i < catalogue.size(); ++i) {
    if (fit.bounds[i] == BoundState::kInside || !catalogue[i].log_scale) continue;
    if (fit.bounds[i] == BoundState::kAtLower) widened[i].lower /= kWidening;
    if (fit.bounds[i] == BoundState::kAtUpper) widened[i].upper *= kWidening;
    widen = true;
  }
  if (!widen) return fit;
  FitOutcome again = Polish(objective, widened, UnitOf(widened, fit.values), fit.mse);
  const std::vector<BoundState> found = fit.bounds;
  if (again.mse < fit.mse) {
    again.evaluations += fit.evaluations;
    again.local_starts += fit.local_starts;
    fit = std::move(again);
  } else {
    fit.evaluations += again.evaluations;
    fit.local_starts += again.local_starts;
  }
  ranges = widened;
  fit.bounds = BoundsOf(widened, fit.values);
  for (std::size_t i = 0; i < catalogue.size(); ++i) {
    if (!catalogue[i].log_scale) {
      fit.bounds[i] = found[i];  // its range cannot widen: where it was found
    } else if (fit.bounds[i] == BoundState::kInside &&
               (fit.values[i] < catalogue[i].lower || fit.values[i] > catalogue[i].upper)) {
      fit.bounds[i] = BoundState::kBeyond;
    }
  }
  return fit;
}

// Thrown out of the swarm's evaluator when the race abandons the fit: pagmo's evolve has no other way to stop.
struct FitAbandoned {
  std::string why;
  FitOutcome converged;  // the local stages from the swarm's best point at the race
};

// The points the race polishes: the swarm's best so far, and the best of the caller's starts (the scan's) when it
// fits better than that. The swarm starts from the refit's values, and the refit can have taken up the effect's
// signature (a 3° backlash on the A-Series halves the refit's P gain): after a few generations the swarm's best is
// still in the refit's basin, while the scan at the model's own values lies in the effect's. Judged from the
// swarm's point alone, such a candidate was abandoned with the truth among its starts. Only a start that already
// fits better is polished: polishing every candidate's scan start took the A-Series example from 117 s to 205 s.
FitOutcome PolishRaceStarts(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                            const FitOptions& options, const FitWatch& swarm) {
  std::vector<Start> starts = {{swarm.best_x, swarm.best_f}};
  std::vector<Start> better;
  for (const FitStart& start : options.starts) {
    if (start.mse < swarm.best_f) better.push_back({UnitOf(parameters, start.values), start.mse});
  }
  AddBestDistinct(std::move(better), 2, starts);
  return BestOf(PolishFrom(objective, parameters, starts));
}

// The race, once the swarm has run FitOptions::abandon_after generations. A fit is never abandoned unconverged: a
// Levenberg–Marquardt polish first runs from the swarm's best point, and where it does not converge the local stages
// (a compass search, whose step shrinks until it converges or its budget ends, and a last polish) go on from where
// it stopped; the question is asked of where they end. A reason, and the polish converged: throws
// FitAbandoned with that fit. Otherwise the polished point becomes one more start (`rescued`), and the swarm goes on
// as if never asked.
void Race(const ReplayObjective& objective, const std::vector<FitParameter>& parameters, const FitOptions& options,
          const FitWatch& swarm, std::optional<FitOutcome>& rescued) {
  if (swarm.swarm_batches != options.abandon_after || !options.abandon) return;
  FitOutcome local = PolishRaceStarts(objective, parameters, options, swarm);
  if (!local.converged) {  // the local stages from where the polish stopped: the compass search converges by its step
    FitOutcome stages = LocalStages(objective, parameters, options, UnitOf(parameters, local.values), local.mse);
    if (!(stages.mse <= local.mse)) std::tie(stages.values, stages.mse) = std::tie(local.values, local.mse);
    stages.evaluations += local.evaluations;
    local = std::move(stages);
  }
  const std::string why = options.abandon(local.values, local.mse);
  if (why.empty() || !local.converged) {  // never abandoned unconverged: the swarm goes on
    rescued = std::move(local);
    return;
  }
  throw FitAbandoned{"abandoned after " + std::to_string(options.abandon_after) +
                         " generations, converged from its best point: " + why,
                     std::move(local)};
}

// A fit given up in its swarm: the converged local search from the swarm's best point, without confidence
// intervals.
FitOutcome Abandoned(const std::vector<FitParameter>& parameters, const FitWatch& swarm, FitAbandoned abandoned) {
  FitOutcome outcome = std::move(abandoned.converged);
  outcome.generations = swarm.swarm_batches;
  outcome.evaluations += static_cast<int>(swarm.evaluated);
  outcome.abandoned = true;
  outcome.convergence = abandoned.why + " (" + outcome.convergence + ")";
  outcome.bounds = BoundsOf(parameters, outcome.values);
  outcome.ci95.assign(parameters.size(), std::numeric_limits<double>::quiet_NaN());
  return outcome;
}

// FitOptions::islands CMA-ES runs from the swarm's last generation, each with its own seed and its own problem
// (pagmo 2.18's cmaes evaluates one point at a time, so the islands run side by side to keep several replays in
// flight). Every replay runs to its end: CMA-ES ranks all its points. Returns each island's best.
std::vector<Start> RunIslands(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                              const FitOptions& options, const pagmo::population& swarm, int& evaluations) {
  FitOptions whole = options;
  whole.stop_replays_early = false;
  std::vector<std::future<std::pair<pagmo::population, std::uint64_t>>> runs;
  for (int i = 0; i < options.islands; ++i) {
    runs.push_back(std::async(std::launch::async, [&, i] {
      auto watch = std::make_shared<FitWatch>();
      watch->options = &whole;
      watch->parameters = &parameters;
      const unsigned seed = options.seed + 1000u + static_cast<unsigned>(i);
      pagmo::population island(ReplayProblem(objective, watch), 0u, seed);
      for (const pagmo::vector_double& x : swarm.get_x()) island.push_back(x);
      const pagmo::cmaes cmaes(static_cast<unsigned>(options.island_generations), -1, -1, -1, -1, kIslandStep, 1e-6,
                               1e-6, false, /*force_bounds=*/true, seed);
      island = pagmo::algorithm{cmaes}.evolve(island);
      return std::make_pair(std::move(island), watch->evaluated);  // points replayed (a repeated point is cached)
    }));
  }
  std::vector<Start> bests;
  for (auto& run : runs) {
    const auto [island, replayed] = run.get();
    evaluations += static_cast<int>(replayed);
    bests.push_back({island.champion_x(), island.champion_f()[0]});
  }
  return bests;
}

}  // namespace

FitOutcome Fit(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
               const FitOptions& options) {
  const auto dimension = static_cast<double>(parameters.size());
  const int size = options.population > 0
                       ? options.population
                       : std::max(16, 8 + static_cast<int>(std::floor(6.0 * std::log(dimension))));
  auto watch = std::make_shared<FitWatch>();
  watch->options = &options;
  watch->parameters = &parameters;
  std::optional<FitOutcome> rescued;  // the race's converged fit, when the race kept the candidate
  pagmo::problem problem = ReplayProblem(objective, watch, [&objective, &parameters, &options, &watch, &rescued] {
    Race(objective, parameters, options, *watch, rescued);
  });
  const pagmo::bfe batch{pagmo::member_bfe{}};
  pagmo::population population(problem, batch, static_cast<pagmo::population::size_type>(size), options.seed);
  // The search starts from the given point: it replaces the worst of the random initial individuals.
  pagmo::vector_double start;
  for (const FitParameter& p : parameters) start.push_back(ToUnit(p, p.start));
  population.set_x(population.worst_idx(), start);

  // 1. Global: pagmo 2.18's CMA-ES evaluates one point at a time; its generational particle swarm takes a batch
  // evaluator, so a whole generation goes to the broker at once (docs/gap.md, "How a fit works").
  pagmo::pso_gen swarm(static_cast<unsigned>(options.generations), 0.7298, 2.05, 2.05, 0.5, 5, 2, 4, false,
                       options.seed);
  swarm.set_bfe(pagmo::bfe{SwarmBatch{watch}});
  for (const pagmo::vector_double& f : population.get_f()) watch->particle_best.push_back(f[0]);
  watch->swarm_batches = 0;
  try {
    population = pagmo::algorithm{swarm}.evolve(population);
  } catch (FitAbandoned& abandoned) {
    return Abandoned(parameters, *watch, std::move(abandoned));
  }
  const int swarm_generations = watch->swarm_batches;
  watch->swarm_batches = -1;  // the race is over
  int evaluations = static_cast<int>(watch->evaluated);

  // 2. The starts of the local stages, from the swarm's particles (pso_gen leaves each particle's best in the
  // population), the caller's points (the scan's) and the CMA-ES islands' bests.
  std::vector<Start> particles;
  for (std::size_t i = 0; i < population.size(); ++i) {
    particles.push_back({population.get_x()[i], population.get_f()[i][0]});
  }
  std::vector<std::vector<Start>> others(1);
  for (const FitStart& offered : options.starts) others[0].push_back({UnitOf(parameters, offered.values), offered.mse});
  if (options.islands > 0) others.push_back(RunIslands(objective, parameters, options, population, evaluations));
  const std::vector<Start> starts = ChooseStarts(particles, others, options.local_starts);

  // 3. The local stages; the race's polished point is one more finished search. Their convergence test is the fit's.
  FitOutcome outcome = options.least_change ? LeastChangeOfTheLocalStages(objective, parameters, options, starts, rescued)
                                            : LocalStagesFromTheBestPolish(objective, parameters, options, starts, rescued);

  // 4. A parameter at a bound: re-searched beyond it, or reported. 5. The intervals of the best.
  std::vector<FitParameter> ranges = parameters;
  outcome = ReSearchBeyondBounds(objective, ranges, std::move(outcome));
  outcome.ci95 = ConfidenceIntervals(objective, ranges, outcome.values, outcome.evaluations);
  outcome.evaluations += evaluations;
  outcome.generations = swarm_generations;
  return outcome;
}

}  // namespace orcs::identify
