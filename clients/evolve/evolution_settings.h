// How `orcs-batch evolve` searches a scenario's genome (docs/evolution.md): the scenario's "evolution" section —
// bounds for every gene, the algorithm, the population, the generations — with the command line's options on top.
// Everything is checked here, before anything is submitted: a population the algorithm cannot run with, bounds of
// the wrong length, a start genome outside its bounds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "clients/runtime/batch_input.h"

namespace orcs::evolve {

/// The range of one gene.
struct GeneBounds {
  double low = 0.0;   ///< smallest value, in the gene's own unit (a weight, degrees, Hz, ...)
  double high = 1.0;  ///< largest value, > low
};

/// The pagmo2 algorithms orcs-batch evolve offers.
enum class Algorithm { kCmaes, kXnes, kSga, kDe, kPsoGen };

/// Everything that decides the search; the checkpoint's fingerprint holds all of it.
struct EvolutionSettings {
  Algorithm algorithm = Algorithm::kCmaes;  ///< "algorithm" / --algorithm
  int population = 16;                      ///< "population" / --population: genomes per generation
  int generations = 30;                     ///< "generations" / --generations: generations after the first
  std::uint64_t seed = 1;                   ///< "seed" / --seed: the jobs' seed (parameter sets) and the optimiser's
  double sigma = 0.3;                       ///< "sigma": CMA-ES/xNES initial step, in units of each gene's range
  int validate = 8;                         ///< "validate" / --validate: fresh seeds the winner is re-run on
  /// "fresh_sets" / --fresh-sets: every generation's jobs get their own seed (GenerationSeed), so the genomes meet
  /// new parameter sets each generation; false: every job has `seed`, the same K sets throughout.
  bool fresh_sets = false;
  std::vector<GeneBounds> bounds;           ///< "bounds": one range per gene, genome order
  std::vector<double> start;                ///< the scenario's "genome", the first individual ([] = none)
};

/// Command-line values that replace the scenario's ("unset" ones keep it).
struct EvolutionOverrides {
  std::string algorithm;   ///< "" = unset
  int population = 0;      ///< 0 = unset
  int generations = -1;    ///< < 0 = unset
  std::int64_t seed = -1;  ///< < 0 = unset
  int validate = -1;       ///< < 0 = unset
  bool fresh_sets = false; ///< --fresh-sets given (false = the scenario's)
};

/// The seed of generation `generation`'s jobs: `seed` itself, or with fresh_sets one drawn from the stream
/// (seed, "evolve-generation-sets", generation) — never one of the validation seeds seed+1…seed+validate but by a
/// chance of 2⁻⁶⁴ per seed.
std::uint64_t GenerationSeed(const EvolutionSettings& settings, int generation);

/// "cmaes", "xnes", "sga", "de", "pso_gen" (the names docs/evolution.md uses).
std::string AlgorithmName(Algorithm algorithm);
/// The smallest population pagmo2 runs `algorithm` with.
int MinimumPopulation(Algorithm algorithm);

/// Reads the scenario's "evolution" section and applies `overrides`. The genome must be a flat array (the
/// scenario's controller's free slots). Throws InputError naming the scenario file and field (or the option):
/// a missing section or bounds, bounds of the wrong length or with low ≥ high, an unknown algorithm, a population
/// below the algorithm's minimum, a start genome outside its bounds.
EvolutionSettings ReadEvolutionSettings(const runtime::ScenarioInput& input, const EvolutionOverrides& overrides);

}  // namespace orcs::evolve
