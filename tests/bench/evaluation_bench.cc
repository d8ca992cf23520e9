// What a job costs, whole and in set-up alone: 40 jobs of the evolution example (the A-Series rocking under
// an oscillator, its evolved winner, 4 s at 10 ms, 6 randomised parameter sets each; seeds 1-40) through
// evaluation::Evaluate, and the same 40 jobs cut to one step, so that only building each set's world counts.
// Run the binary of two builds side by side (docs/benchmarks.md) to compare world building per set with once
// per job.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "model/evaluation/evaluation.h"
#include "model/scene/scenario.h"

namespace orcs::evaluation {
namespace {

constexpr int kJobs = 40;

EvaluationRequest EvolutionJob(std::uint64_t seed, bool one_step) {
  const std::string folder = std::string(ORCS_SOURCE_DIR) + "/scenarios/evolution/";
  EvaluationRequest request;
  request.scenario = scene::ParseScenario(scene::ResolveScenarioFile(folder + "rock_oscillator.json"),
                                          folder + "rock_oscillator.json");
  std::ifstream winner(folder + "rock_oscillator.winner.json");
  request.genome = nlohmann::json::parse(winner);
  request.seed = seed;
  if (one_step) request.scenario.duration = 0.01;
  return request;
}

void RunJobs(benchmark::State& state, bool one_step) {
  std::vector<EvaluationRequest> jobs;
  for (int j = 1; j <= kJobs; ++j) jobs.push_back(EvolutionJob(static_cast<std::uint64_t>(j), one_step));
  std::size_t sets = 0;
  for (auto _ : state) {
    for (const EvaluationRequest& job : jobs) {
      const EvaluationOutcome outcome = Evaluate(job);
      if (outcome.status != EvaluationStatus::kOk) {
        state.SkipWithError(outcome.message.c_str());
        return;
      }
      sets += outcome.sets.size();
      benchmark::DoNotOptimize(outcome.fitness);
    }
  }
  state.counters["jobs_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kJobs,
                                                    benchmark::Counter::kIsRate);
  state.counters["sets_per_job"] = static_cast<double>(sets) / static_cast<double>(state.iterations() * kJobs);
}

// 40 whole jobs: 40 × 6 × 400 steps.
void BM_EvolutionJobs(benchmark::State& state) { RunJobs(state, false); }
BENCHMARK(BM_EvolutionJobs)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The same 40 jobs, one step per set: what is left is each set's world, controller and fitness set-up.
void BM_EvolutionJobsSetUpOnly(benchmark::State& state) { RunJobs(state, true); }
BENCHMARK(BM_EvolutionJobsSetUpOnly)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

}  // namespace
}  // namespace orcs::evaluation

BENCHMARK_MAIN();
