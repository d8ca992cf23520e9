// What orcs-batch evolve's one-batch-per-generation costs on top of pagmo: a generation through Evolution::Step
// (rehearsal + batch + real pass) against plain pagmo evolving the same population with direct evaluation, for
// each algorithm, 10 genes, 16 genomes, an analytic fitness so that only the optimiser's own work is timed.
// A simulated genome costs about 0.2 s of worker time (docs/benchmarks.md); this is the overhead per generation.
#include <benchmark/benchmark.h>

#include <pagmo/problem.hpp>

#include "clients/evolve/evolution.h"

namespace orcs::evolve {
namespace {

constexpr std::size_t kGenes = 10;
constexpr int kPopulation = 16;

double Fitness(const std::vector<double>& genome) {
  double sum = 0.0;
  for (std::size_t i = 0; i < genome.size(); ++i)
    sum += (genome[i] - 0.1 * static_cast<double>(i)) * (genome[i] - 0.1 * static_cast<double>(i));
  return -sum;
}

EvolutionSettings Settings(Algorithm algorithm) {
  EvolutionSettings settings;
  settings.algorithm = algorithm;
  settings.population = kPopulation;
  settings.bounds.assign(kGenes, {-1.0, 1.0});
  return settings;
}

std::vector<Evaluation> Analytic(const std::vector<std::vector<double>>& genomes, std::uint64_t) {
  std::vector<Evaluation> evaluations;
  for (const std::vector<double>& genome : genomes) evaluations.push_back({Fitness(genome), true});
  return evaluations;
}

// The same problem pagmo evaluates directly, in the unit box like BatchProblem.
struct DirectProblem {
  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    std::vector<double> genome(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) genome[i] = -1.0 + 2.0 * x[i];
    return {-Fitness(genome)};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {pagmo::vector_double(kGenes, 0.0), pagmo::vector_double(kGenes, 1.0)};
  }
};

void BM_EvolutionStep(benchmark::State& state) {
  const auto algorithm = static_cast<Algorithm>(state.range(0));
  Evolution evolution(Settings(algorithm), Analytic);
  evolution.Initialise();
  for (auto _ : state) evolution.Step();
  state.SetLabel(AlgorithmName(algorithm));
}

void BM_PlainPagmoGeneration(benchmark::State& state) {
  const auto algorithm = static_cast<Algorithm>(state.range(0));
  pagmo::algorithm pagmo_algorithm = MakeAlgorithm(Settings(algorithm));
  pagmo::population population(pagmo::problem{DirectProblem{}}, kPopulation, 1u);
  for (auto _ : state) population = pagmo_algorithm.evolve(population);
  state.SetLabel(AlgorithmName(algorithm));
}

BENCHMARK(BM_EvolutionStep)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PlainPagmoGeneration)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace orcs::evolve

BENCHMARK_MAIN();
