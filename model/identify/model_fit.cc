#include "model/identify/model_fit.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <pagmo/algorithm.hpp>
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

// The pagmo problem: evolve's unit-box BatchProblem, whose cache evaluates what pagmo asks for as one batch of
// replays (member_bfe calls batch_fitness; every generation is one call).
pagmo::problem ReplayProblem(const ReplayObjective& objective, const std::vector<FitParameter>& parameters) {
  auto cache = std::make_shared<GenerationCache>();
  cache->evaluate = [&objective, &parameters](const std::vector<pagmo::vector_double>& xs) {
    std::vector<std::vector<Override>> points;
    for (const pagmo::vector_double& x : xs) points.push_back(OverridesOf(parameters, Values(parameters, x.data())));
    return objective.MeanSquaredErrors(points);
  };
  return pagmo::problem{BatchProblem(parameters.size(), std::move(cache))};
}

// The polish stops when its step has shrunk below kPolishStop of the (normalised) range, or after its budget.
constexpr double kPolishStart = 0.05;
constexpr double kPolishStop = 0.002;
constexpr unsigned kPolishBudgetPerDimension = 40;

struct SwarmOutcome {
  pagmo::population population;  // its champion is the swarm's best point
  int generations = 0;           // generations run
  bool abandoned = false;        // stopped above FitOptions::abandon_above
  std::string why;               // why it stopped, one line
};

// The particle swarm in rounds of kSwarmRound generations: it stops at its budget, when its best stalled over the
// last stall_generations, or, abandoned, when it is still above abandon_above after abandon_after.
SwarmOutcome RunSwarm(pagmo::population population, const pagmo::bfe& batch, const FitOptions& options) {
  const auto swarm_of = [&](int generations, unsigned seed) {
    pagmo::pso_gen swarm(static_cast<unsigned>(generations), 0.7298, 2.05, 2.05, 0.5, 5, 2, 4, /*memory=*/true, seed);
    swarm.set_bfe(batch);
    return pagmo::algorithm{swarm};
  };
  SwarmOutcome outcome{population, 0, false, ""};
  if (options.stall_generations <= 0 && std::isinf(options.abandon_above)) {  // no early stop: one run, no memory
    pagmo::pso_gen swarm(static_cast<unsigned>(options.generations), 0.7298, 2.05, 2.05, 0.5, 5, 2, 4, false,
                         options.seed);
    swarm.set_bfe(batch);
    outcome.population = pagmo::algorithm{swarm}.evolve(population);
    outcome.generations = options.generations;
    return outcome;
  }
  const pagmo::algorithm round = swarm_of(kSwarmRound, options.seed);
  std::vector<double> best_after;  // the best objective after each generation run so far (at round ends)
  while (outcome.generations < options.generations) {
    const int left = options.generations - outcome.generations;
    // A last, shorter round is a swarm of its own (its velocities start afresh, its generator from seed + 1).
    outcome.population =
        left >= kSwarmRound ? round.evolve(outcome.population) : swarm_of(left, options.seed + 1).evolve(outcome.population);
    outcome.generations += std::min(left, kSwarmRound);
    const double best = outcome.population.champion_f()[0];
    best_after.resize(static_cast<std::size_t>(outcome.generations), best);
    if (outcome.generations >= options.abandon_after && best > options.abandon_above) {
      outcome.abandoned = true;
      outcome.why = "abandoned after " + std::to_string(outcome.generations) + " generations: its best error, " +
                    text::FormatDouble(best) + " deg², stayed above " + text::FormatDouble(options.abandon_above) +
                    " deg², so it cannot win";
      return outcome;
    }
    const int window = options.stall_generations;
    if (window > 0 && outcome.generations > window && outcome.generations < options.generations) {
      const double before = best_after[static_cast<std::size_t>(outcome.generations - window - 1)];
      if (before - best < options.stall_tolerance * before) {
        outcome.why = "the swarm stalled after " + std::to_string(outcome.generations) + " generations";
        return outcome;
      }
    }
  }
  return outcome;
}

// A fit given up after its swarm: its best point as found, with no local stages and no confidence intervals.
FitOutcome Abandoned(const std::vector<FitParameter>& parameters, const pagmo::population& population,
                     const SwarmOutcome& swarm) {
  FitOutcome outcome;
  outcome.values = Values(parameters, population.champion_x().data());
  outcome.mse = population.champion_f()[0];
  outcome.generations = swarm.generations;
  outcome.evaluations = static_cast<int>(population.get_problem().get_fevals());
  outcome.abandoned = true;
  outcome.convergence = "did not converge: " + swarm.why + " (the limit is set by the diagnosis)";
  outcome.polish = "not run: the fit was abandoned";
  outcome.ci95.assign(parameters.size(), std::numeric_limits<double>::quiet_NaN());
  return outcome;
}

}  // namespace

ReplayObjective::ReplayObjective(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs,
                                 std::vector<Override> fixed)
    : replays_(replays), runs_(runs), fixed_(std::move(fixed)) {}

std::vector<double> ReplayObjective::MeanSquaredErrors(const std::vector<std::vector<Override>>& points) const {
  std::vector<ReplayRequest> requests;
  for (const std::vector<Override>& point : points) {
    std::vector<Override> overrides = fixed_;
    overrides.insert(overrides.end(), point.begin(), point.end());
    for (const ReplayRun& run : runs_) requests.push_back({&run, overrides});
  }
  const std::vector<ReplayOutcome> outcomes = replays_.Replay(requests);
  std::vector<double> errors;
  std::size_t next = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    double sum = 0.0;
    double samples = 0.0;
    bool failed = false;
    for (const ReplayRun& run : runs_) {
      const ReplayOutcome& outcome = outcomes[next++];
      failed = failed || !outcome.ok || !std::isfinite(outcome.rms);
      sum += outcome.rms * outcome.rms * static_cast<double>(run.samples);
      samples += static_cast<double>(run.samples);
    }
    errors.push_back(failed || samples == 0.0 ? kFailedPoint : sum / samples);
  }
  return errors;
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

std::vector<Override> OverridesOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::vector<Override> overrides;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    overrides.emplace_back(parameters[i].path, text::FormatDouble(values[i]));
  }
  return overrides;
}

FitOutcome Fit(const ReplayObjective& objective, const std::vector<FitParameter>& parameters,
               const FitOptions& options) {
  const auto dimension = static_cast<double>(parameters.size());
  const int size = options.population > 0
                       ? options.population
                       : std::max(16, 8 + static_cast<int>(std::floor(6.0 * std::log(dimension))));
  pagmo::problem problem = ReplayProblem(objective, parameters);
  const pagmo::bfe batch{pagmo::member_bfe{}};
  pagmo::population population(problem, batch, static_cast<pagmo::population::size_type>(size), options.seed);
  // The search starts from the given point: it replaces the worst of the random initial individuals.
  pagmo::vector_double start;
  for (const FitParameter& p : parameters) start.push_back(ToUnit(p, p.start));
  population.set_x(population.worst_idx(), start);

  // 1. Global: pagmo 2.18's CMA-ES evaluates one point at a time; its generational particle swarm takes a batch
  // evaluator, so a whole generation goes to the broker at once (docs/gap.md, "How a fit works").
  const SwarmOutcome swarm = RunSwarm(population, batch, options);
  population = swarm.population;
  const auto swarm_evaluations = population.get_problem().get_fevals();
  if (swarm.abandoned) return Abandoned(parameters, population, swarm);

  // 2. Local: a compass search from the swarm's best point until its step is small — the convergence test.
  pagmo::population polish(problem, 0u, options.seed);
  polish.push_back(population.champion_x(), population.champion_f());
  const unsigned budget = kPolishBudgetPerDimension * static_cast<unsigned>(parameters.size());
  polish = pagmo::algorithm{pagmo::compass_search(budget, kPolishStart, kPolishStop, 0.5)}.evolve(polish);
  const auto polish_evaluations = polish.get_problem().get_fevals();

  // 3. Least squares: Levenberg–Marquardt on the residuals, and the confidence intervals.
  const PolishOutcome squares =
      PolishLeastSquares(objective, parameters, Values(parameters, polish.champion_x().data()));

  FitOutcome outcome;
  outcome.values = squares.values;
  outcome.mse = std::min(squares.mse, polish.champion_f()[0]);
  outcome.polish = squares.summary;
  outcome.ci95 = squares.ci95;
  outcome.evaluations = static_cast<int>(swarm_evaluations + polish_evaluations) + squares.evaluations;
  outcome.generations = swarm.generations;
  outcome.converged = polish_evaluations < budget;
  outcome.convergence =
      outcome.converged
          ? "converged: the local search's step fell below " + text::FormatDouble(kPolishStop * 100.0) +
                " % of every parameter's range after " + std::to_string(polish_evaluations) + " evaluations"
          : "did not converge: the local search used its whole budget of " + std::to_string(budget) +
                " evaluations with its step still above " + text::FormatDouble(kPolishStop * 100.0) + " % of the range";
  outcome.convergence += swarm.why.empty()
                             ? "; the swarm ran its whole budget of " + std::to_string(swarm.generations) + " generations"
                             : "; " + swarm.why;
  return outcome;
}

}  // namespace orcs::identify
