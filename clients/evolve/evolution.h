// One evolution run of orcs-batch evolve (docs/evolution.md): a pagmo2 algorithm over a scenario's genome, one
// generation at a time, every generation's genomes evaluated as one batch (BatchProblem). Holds the search state —
// the algorithm, the population, the best genome so far and the history — and writes it to a checkpoint and reads
// it back, so an interrupted run continues exactly where it stopped.
//
// The evaluator is a function: the command passes one that runs jobs through the broker; tests pass analytic ones.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <pagmo/algorithm.hpp>
#include <pagmo/population.hpp>
#include <string>
#include <vector>

#include "model/identify/batch_problem.h"
#include "clients/evolve/evolution_settings.h"

namespace orcs::evolve {

using identify::BatchProblem;     // the unit-box pagmo problem evolve shares with the gap workflow
using identify::GenerationCache;  // its record / lookup cache

/// What one genome's evaluation gave.
struct Evaluation {
  double fitness = 0.0;  ///< the job's fitness (higher is better); meaningless when !ok
  bool ok = false;       ///< the job ran (status ok)
};

/// Evaluates genomes (in the genes' own units) as one batch of jobs with seed `seed` (the generation's,
/// GenerationSeed); one Evaluation per genome, in order.
using GenomeEvaluator =
    std::function<std::vector<Evaluation>(const std::vector<std::vector<double>>&, std::uint64_t seed)>;

/// One generation, as fitness.csv lists it.
struct GenerationRecord {
  int generation = 0;           ///< 0 = the initial population
  std::size_t evaluations = 0;  ///< genomes evaluated in this generation
  std::size_t failed = 0;       ///< of them, jobs that did not run ok (scored as the worst possible)
  double best = 0.0;            ///< highest fitness of this generation's ok evaluations (NaN when none)
  double mean = 0.0;            ///< their mean (NaN when none)
  double median = 0.0;          ///< their median (NaN when none)
  double worst = 0.0;           ///< their lowest (NaN when none)
  double best_so_far = 0.0;     ///< the champion's fitness after this generation (NaN before any ok job)
  double seconds = 0.0;         ///< wall clock of the generation, s (not part of the search: not reproducible)
};

/// The best genome evaluated so far.
struct Champion {
  std::vector<double> genome;  ///< genes in their own units ([] before any ok evaluation)
  double fitness = 0.0;        ///< its fitness
  int generation = -1;         ///< the generation that found it
  std::uint64_t seed = 0;      ///< the seed of the job that scored it (its generation's): its replay's seed
};

/// Objective of a genome whose job failed: worse than any real fitness, finite for the algorithms' arithmetic.
inline constexpr double kFailedObjective = 1e30;

class Evolution {
 public:
  /// A fresh run; nothing is evaluated until Initialise().
  Evolution(EvolutionSettings settings, GenomeEvaluator evaluate);
  Evolution(const Evolution&) = delete;  // the cache's evaluator refers to this object
  Evolution& operator=(const Evolution&) = delete;

  /// Generation 0: the scenario's start genome (when given) and population − 1 random genomes in the bounds
  /// (drawn from the stream (seed, "evolve-initial-population", i)), evaluated as one batch.
  void Initialise();
  /// One generation of the algorithm: its genomes evaluated as one batch. Needs Initialise() or Restore() first.
  void Step();

  /// The algorithm and population as text (boost archive; exact doubles), for the checkpoint.
  std::string SaveState() const;
  /// Continues a run from a checkpoint's state, history and champion. Throws InputError when the state does not
  /// read back (a damaged checkpoint) or the algorithm cannot be resumed exactly (CheckResumable), naming `source`.
  void Restore(const std::string& state, std::vector<GenerationRecord> history, Champion champion,
               const std::string& source);

  /// Generations done: 0 after Initialise(), +1 per Step().
  int generation() const { return history_.empty() ? -1 : history_.back().generation; }
  const std::vector<GenerationRecord>& history() const { return history_; }
  const Champion& champion() const { return champion_; }
  const EvolutionSettings& settings() const { return settings_; }
  /// Vectors the algorithm asked for that the recording pass had not seen (evaluated alone).
  std::size_t cache_misses() const { return cache_->misses; }
  /// The algorithm's population: decision vectors in the unit box, objectives −fitness (read-only, for tests).
  const pagmo::population& population() const { return population_; }

  /// The genome a unit-box decision vector stands for, and back.
  std::vector<double> GenomeOf(const pagmo::vector_double& x) const;
  pagmo::vector_double DecisionVectorOf(const std::vector<double>& genome) const;

 private:
  std::vector<double> EvaluateBatch(const std::vector<pagmo::vector_double>& xs);
  void CloseGeneration(int generation, double seconds);

  EvolutionSettings settings_;
  GenomeEvaluator evaluate_;
  std::shared_ptr<GenerationCache> cache_;
  pagmo::algorithm algorithm_;
  pagmo::population population_;
  std::vector<GenerationRecord> history_;
  Champion champion_;
  std::vector<Evaluation> current_;  ///< the evaluations of the generation under way
  int evaluating_ = 0;               ///< the generation under way (its jobs' seed: GenerationSeed)
};

/// The pagmo2 algorithm the settings name, running one generation per evolve() call and keeping its adapted
/// state between calls (CMA-ES, xNES, pso_gen: memory on), seeded from settings.seed.
pagmo::algorithm MakeAlgorithm(const EvolutionSettings& settings);

/// Throws InputError naming `source` when a run of `algorithm` cannot continue exactly from SaveState(): pso_gen,
/// whose particles' velocities (its memory between generations) pagmo 2.18 leaves out of the saved state, so a
/// resumed run would search differently from an uninterrupted one.
void CheckResumable(Algorithm algorithm, const std::string& source);

}  // namespace orcs::evolve
