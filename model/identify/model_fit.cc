#include "model/identify/model_fit.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <future>
#include <map>
#include <memory>
#include <tuple>
#include <pagmo/algorithm.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/compass_search.hpp>
#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/batch_evaluators/member_bfe.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

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

// What a fit's evaluations have seen, for the race (FitOptions::abandon): the best point and how many batches the
// swarm has sent. Shared by the problem's evaluator and Fit.
struct FitWatch {
  const FitOptions* options = nullptr;
  const std::vector<FitParameter>* parameters = nullptr;
  pagmo::vector_double best_x;                             // the best point evaluated so far (unit box)
  double best_f = std::numeric_limits<double>::infinity();  // its objective, deg²
  std::uint64_t evaluated = 0;                             // points evaluated through the problem
  int swarm_batches = -1;                                  // generations of the swarm so far; −1 before it starts
  double first_generation_best = std::numeric_limits<double>::infinity();  // best_f after the swarm's first, deg²
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
    assert(xs.size() == w.particle_best.size() * n && "the swarm's batch is one point per particle");
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

// Thrown out of the swarm's evaluator when the race abandons the fit: pagmo's evolve has no other way to stop.
struct FitAbandoned {
  std::string why;
};

// What the race cannot tell apart: a swarm whose best has not changed since its first generation may not have
// started to search yet (on the XL330 logs GearEfficiency's swarm sat at its start until generation 21, then
// won). Said with the verdict, so that the user knows when --no-race is worth a run.
std::string StalledSince(const FitWatch& watch) {
  if (watch.best_f < watch.first_generation_best) return "";  // as FitOutcome::abandoned_unmoved
  return "; its best had not changed since the swarm's first generation, so its search may not have started "
         "(--no-race fits every candidate to the end)";
}

// The pagmo problem: evolve's unit-box BatchProblem, whose cache evaluates what pagmo asks for as one batch of
// replays (member_bfe calls batch_fitness; every generation is one call). After the swarm's abandon_after-th
// generation the race is asked about the best point so far.
pagmo::problem ReplayProblem(const ReplayObjective& objective, const std::shared_ptr<FitWatch>& watch) {
  auto cache = std::make_shared<GenerationCache>();
  cache->evaluate = [&objective, watch](const std::vector<pagmo::vector_double>& xs) {
    const std::vector<FitParameter>& parameters = *watch->parameters;
    std::vector<std::vector<Override>> points;
    for (const pagmo::vector_double& x : xs) points.push_back(OverridesOf(parameters, Values(parameters, x.data())));
    const FitOptions& options = *watch->options;
    std::vector<double> bounds;
    if (options.stop_replays_early) {
      for (const pagmo::vector_double& x : xs) bounds.push_back(watch->BoundOf(x));
    }
    const std::vector<double> errors = objective.Losses(points, bounds);
    watch->evaluated += xs.size();
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (errors[i] < watch->best_f) std::tie(watch->best_x, watch->best_f) = std::tie(xs[i], errors[i]);
      if (watch->in_compass) watch->compass_best = std::min(watch->compass_best, errors[i]);
    }
    if (watch->swarm_batches >= 0 && ++watch->swarm_batches == 1) watch->first_generation_best = watch->best_f;
    if (watch->swarm_batches == options.abandon_after && options.abandon) {
      const std::string why = options.abandon(Values(parameters, watch->best_x.data()), watch->best_f);
      if (!why.empty()) {
        throw FitAbandoned{"abandoned after " + std::to_string(options.abandon_after) + " generations: " + why +
                           StalledSince(*watch)};
      }
    }
    return errors;
  };
  return pagmo::problem{BatchProblem(watch->parameters->size(), std::move(cache))};
}

// The polish stops when its step has shrunk below kPolishStop of the (normalised) range, or after its budget.
constexpr double kPolishStart = 0.05;
constexpr double kPolishStop = 0.002;
constexpr unsigned kPolishBudgetPerDimension = 40;
constexpr int kQuickLookIterations = 5;
// The CMA-ES islands' first step, as a share of the unit box: wide enough to leave the swarm's basin.
constexpr double kIslandStep = 0.3;

// A fit given up in its swarm: the best point seen (the quick look's included), with no local stages and no
// confidence intervals.
FitOutcome Abandoned(const std::vector<FitParameter>& parameters, const FitWatch& watch, const std::string& why,
                     int look_evaluations) {
  FitOutcome outcome;
  outcome.values = Values(parameters, watch.best_x.data());
  outcome.mse = watch.best_f;
  outcome.generations = watch.swarm_batches;
  outcome.evaluations = static_cast<int>(watch.evaluated) + look_evaluations;
  outcome.abandoned = true;
  outcome.abandoned_unmoved = !(watch.best_f < watch.first_generation_best);
  outcome.convergence = "did not converge: " + why;
  outcome.polish = "not run: the fit was abandoned";
  outcome.ci95.assign(parameters.size(), std::numeric_limits<double>::quiet_NaN());
  return outcome;
}

// A quick local look for the race: a few Levenberg–Marquardt steps from the start. The swarm's first generations
// seldom beat a good start, so without it the race would judge little more than the start; an effect that helps
// nearby shows it here. Its point counts as seen (watch) but does not join the swarm, whose search stays the one
// it would be without the race. Returns the replays it took.
int QuickLook(const ReplayObjective& objective, const std::vector<FitParameter>& parameters, FitWatch& watch) {
  std::vector<double> start;
  for (const FitParameter& p : parameters) start.push_back(p.start);
  const PolishOutcome look =
      PolishLeastSquares(objective, parameters, start,
                         {.iterations = kQuickLookIterations, .intervals = false});
  if (look.improved && look.mse < watch.best_f) {
    watch.best_x.clear();
    for (std::size_t i = 0; i < parameters.size(); ++i) watch.best_x.push_back(ToUnit(parameters[i], look.values[i]));
    watch.best_f = look.mse;
  }
  return look.evaluations;
}

}  // namespace

ReplayObjective::ReplayObjective(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs,
                                 std::vector<Override> fixed, Loss loss)
    : replays_(replays), runs_(runs), fixed_(std::move(fixed)), loss_(loss) {}

double ReplayObjective::RunBound(double bound, const ReplayRun& run) const {
  double samples = 0.0;
  for (const ReplayRun& each : runs_) samples += static_cast<double>(each.samples);
  if (!std::isfinite(bound) || run.samples == 0) return std::numeric_limits<double>::infinity();
  // One run alone beyond this error puts the pooled loss above the bound, whatever the other runs give; the margin
  // keeps that true through the rounding of error² · samples (error · samples).
  constexpr double kRoundingMargin = 1e-9;
  const double share = bound * samples / static_cast<double>(run.samples);
  return (loss_ == Loss::kAbsolute ? share : std::sqrt(share)) * (1.0 + kRoundingMargin);
}

std::vector<double> ReplayObjective::Losses(const std::vector<std::vector<Override>>& points,
                                            const std::vector<double>& bounds) const {
  assert(bounds.empty() || bounds.size() == points.size());
  std::vector<ReplayRequest> requests;
  for (std::size_t p = 0; p < points.size(); ++p) {
    std::vector<Override> overrides = fixed_;
    overrides.insert(overrides.end(), points[p].begin(), points[p].end());
    for (const ReplayRun& run : runs_) {
      ReplayRequest& request = requests.emplace_back(ReplayRequest{&run, overrides});
      request.loss = loss_;
      if (!bounds.empty()) request.stop_above = RunBound(bounds[p], run);
    }
  }
  const std::vector<ReplayOutcome> outcomes = replays_.Replay(requests);
  std::vector<double> losses;
  std::size_t next = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    double sum = 0.0;
    double samples = 0.0;
    bool failed = false;
    for (const ReplayRun& run : runs_) {
      const ReplayOutcome& outcome = outcomes[next++];
      failed = failed || !outcome.ok || !std::isfinite(outcome.error);
      const double per_sample = loss_ == Loss::kAbsolute ? outcome.error : outcome.error * outcome.error;
      sum += per_sample * static_cast<double>(run.samples);
      samples += static_cast<double>(run.samples);
    }
    losses.push_back(failed || samples == 0.0 ? kFailedPoint : sum / samples);
  }
  return losses;
}

std::vector<std::vector<double>> ReplayObjective::Residuals(const std::vector<std::vector<Override>>& points) const {
  std::vector<ReplayRequest> requests;
  for (const std::vector<Override>& point : points) {
    std::vector<Override> overrides = fixed_;
    overrides.insert(overrides.end(), point.begin(), point.end());
    for (const ReplayRun& run : runs_) requests.push_back({&run, overrides, /*log=*/true});
  }
  const std::vector<ReplayOutcome> outcomes = replays_.Replay(requests);
  std::vector<std::vector<double>> residuals;
  std::size_t next = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    std::vector<double>& point = residuals.emplace_back();
    bool failed = false;
    for (const ReplayRun& run : runs_) {
      const ReplayOutcome& outcome = outcomes[next++];
      failed = failed || !outcome.ok;
      for (const std::string& motor : run.channels) {
        const std::vector<double>& measured = run.run->joint_angle.at(motor);
        const std::string path = "/Sim/" + run.run->agent + "/" + motor + "/JointAngle";
        const std::vector<double>* simulated = nullptr;
        for (const auto& [name, values] : outcome.columns) {
          if (name == path) simulated = &values;
        }
        if (simulated == nullptr || simulated->size() < measured.size()) {
          failed = true;
          continue;
        }
        for (std::size_t row = 1; row < measured.size(); ++row) point.push_back((*simulated)[row] - measured[row]);
      }
    }
    const bool finite = std::all_of(point.begin(), point.end(), [](double r) { return std::isfinite(r); });
    if (failed || !finite) point.clear();
  }
  return residuals;
}

std::vector<std::vector<double>> ReplayObjective::LossResiduals(
    const std::vector<std::vector<Override>>& points) const {
  std::vector<std::vector<double>> residuals = Residuals(points);
  if (loss_ == Loss::kAbsolute) {
    for (std::vector<double>& point : residuals) {
      for (double& r : point) r = std::copysign(std::sqrt(std::abs(r)), r);
    }
  }
  return residuals;
}

std::vector<Override> OverridesOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::vector<Override> overrides;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    overrides.emplace_back(parameters[i].path, text::FormatDouble(values[i]));
  }
  return overrides;
}

namespace {

// The local stages from one start: a compass search until its step is small (the convergence test), then
// Levenberg–Marquardt on the residuals with the confidence intervals. `evaluations` counts both.
FitOutcome LocalStages(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                       const pagmo::problem& problem, FitWatch& watch, const pagmo::vector_double& start_x,
                       double start_f, unsigned seed) {
  pagmo::population polish(problem, 0u, seed);
  polish.push_back(start_x, {start_f});
  const unsigned budget = kPolishBudgetPerDimension * static_cast<unsigned>(parameters.size());
  // pagmo's compass search moves only to a trial point strictly better than its current one, so a trial's value
  // matters only below the current point's: that is its bound.
  watch.in_compass = true;
  watch.compass_best = start_f;
  const std::uint64_t replayed_before = watch.evaluated;
  polish = pagmo::algorithm{pagmo::compass_search(budget, kPolishStart, kPolishStop, 0.5)}.evolve(polish);
  watch.in_compass = false;
  // Its budget counts the points it asks for; a point another local search of this fit asked for is cached.
  const auto polish_evaluations = polish.get_problem().get_fevals();
  const std::uint64_t polish_replays = watch.evaluated - replayed_before;

  const PolishOutcome squares =
      PolishLeastSquares(objective, parameters, Values(parameters, polish.champion_x().data()));

  FitOutcome outcome;
  outcome.values = squares.values;
  outcome.mse = std::min(squares.mse, polish.champion_f()[0]);
  outcome.polish = squares.summary;
  outcome.ci95 = squares.ci95;
  outcome.evaluations = static_cast<int>(polish_replays) + squares.evaluations;
  outcome.converged = polish_evaluations < budget;
  outcome.convergence =
      outcome.converged
          ? "converged: the local search's step fell below " + text::FormatDouble(kPolishStop * 100.0) +
                " % of every parameter's range after " + std::to_string(polish_evaluations) + " evaluations"
          : "did not converge: the local search used its whole budget of " + std::to_string(budget) +
                " evaluations with its step still above " + text::FormatDouble(kPolishStop * 100.0) + " % of the range";
  return outcome;
}

struct IslandsOutcome {
  pagmo::vector_double best_x;  // the best point of all islands (unit box)
  double best_f = std::numeric_limits<double>::infinity();
  int evaluations = 0;
};

// FitOptions::islands CMA-ES runs from the swarm's last generation, each with its own seed and its own problem
// (pagmo 2.18's cmaes evaluates one point at a time, so the islands run side by side to keep several replays in
// flight). Every replay runs to its end: CMA-ES ranks all its points.
IslandsOutcome RunIslands(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
                          const FitOptions& options, const pagmo::population& swarm) {
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
  IslandsOutcome outcome;
  for (auto& run : runs) {
    const auto [island, replayed] = run.get();
    outcome.evaluations += static_cast<int>(replayed);
    if (island.champion_f()[0] < outcome.best_f) {
      outcome.best_x = island.champion_x();
      outcome.best_f = island.champion_f()[0];
    }
  }
  return outcome;
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
  pagmo::problem problem = ReplayProblem(objective, watch);
  const pagmo::bfe batch{pagmo::member_bfe{}};
  pagmo::population population(problem, batch, static_cast<pagmo::population::size_type>(size), options.seed);
  // The search starts from the given point: it replaces the worst of the random initial individuals.
  pagmo::vector_double start;
  for (const FitParameter& p : parameters) start.push_back(ToUnit(p, p.start));
  population.set_x(population.worst_idx(), start);
  const int look_evaluations = options.abandon ? QuickLook(objective, parameters, *watch) : 0;

  // 1. Global: pagmo 2.18's CMA-ES evaluates one point at a time; its generational particle swarm takes a batch
  // evaluator, so a whole generation goes to the broker at once (docs/gap.md, "How a fit works").
  pagmo::pso_gen swarm(static_cast<unsigned>(options.generations), 0.7298, 2.05, 2.05, 0.5, 5, 2, 4, false,
                       options.seed);
  swarm.set_bfe(pagmo::bfe{SwarmBatch{watch}});
  for (const pagmo::vector_double& f : population.get_f()) watch->particle_best.push_back(f[0]);
  watch->swarm_batches = 0;
  try {
    population = pagmo::algorithm{swarm}.evolve(population);
  } catch (const FitAbandoned& abandoned) {
    return Abandoned(parameters, *watch, abandoned.why, look_evaluations);
  }
  watch->swarm_batches = -1;  // the race is over
  const auto swarm_evaluations = static_cast<int>(population.get_problem().get_fevals());

  // 2. Local stages from the swarm's best point; 3. from the CMA-ES islands' best, when asked for: the better wins.
  FitOutcome outcome = LocalStages(objective, parameters, problem, *watch, population.champion_x(),
                                   population.champion_f()[0], options.seed);
  int evaluations = swarm_evaluations + outcome.evaluations;
  if (options.islands > 0) {
    const IslandsOutcome islands = RunIslands(objective, parameters, options, population);
    evaluations += islands.evaluations;
    FitOutcome from_islands = LocalStages(objective, parameters, problem, *watch, islands.best_x, islands.best_f,
                                          options.seed);
    evaluations += from_islands.evaluations;
    if (from_islands.mse < outcome.mse) outcome = std::move(from_islands);
  }
  outcome.evaluations = evaluations + look_evaluations;
  outcome.generations = options.generations;
  return outcome;
}

}  // namespace orcs::identify
