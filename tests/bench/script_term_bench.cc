// The cost of a scripted fitness term (issue 50, docs/extending.md), in one process: the standing A-Series on MuJoCo,
// one step and one fitness sample per iteration — no term, the built-in `distance`, the shipped distance.lua (the
// same value, to the bit), the built-in `energy` and energy.lua — and, since a term's cost is far below the step's
// noise on a shared machine, each term's Sample alone on the same robot (BM_Sample/...). docs/benchmarks.md records
// each term's cost as a share of the bare step; the bound: a scripted term costs at most 5 % of a standing
// MuJoCo step.
#include <benchmark/benchmark.h>

#include <fstream>
#include <memory>
#include <sstream>

#include "model/fitness/fitness_function.h"
#include "model/scene/simulation.h"

namespace orcs::fitness {
namespace {

constexpr int kStepsPerRun = 1000;  // 10 s at 10 ms, then the run starts again (outside nothing: a reset is cheap)

std::string Script(const std::string& file) {
  std::ifstream in(std::string(ORCS_SOURCE_DIR) + "/scenarios/examples/scripts/" + file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json Term(const std::string& kind) {
  if (kind == "distance") return {{"type", "distance"}, {"body", "Middle/UpperBody"}, {"axis", "z"}};
  if (kind == "energy") return {{"type", "energy"}};
  return {{"type", "script"}, {"name", kind}, {"script", {{"file", kind}, {"text", Script(kind)}}},
          {"params", {{"body", "Middle/UpperBody"}, {"axis", "z"}}}};
}

// The standing A-Series on MuJoCo, built as a batch job builds it, reset.
void BuildStanding(scene::Simulation& simulation) {
  simulation.repository().Set("/Simulation/Engine", "MuJoCo");
  scene::EnvironmentDescription environment;
  environment.agents.push_back(scene::AgentDescription{});
  simulation.LoadEnvironment(environment);
  simulation.Build();
  simulation.SetExcludedCollisionEvents(false);  // as a batch job runs it
  simulation.Reset(0);
}

// One term's Sample after a step, the robot standing still between calls: the term's own cost per step.
void SampleOnly(benchmark::State& state, const std::string& kind) {
  scene::Simulation simulation;
  BuildStanding(simulation);
  for (int i = 0; i < 10; ++i) simulation.Step();
  FitnessFunction fitness(nlohmann::json{{"terms", {Term(kind)}}}, simulation, 0, "bench");
  fitness.Start(simulation);
  const double dt = simulation.StepDuration();
  std::int64_t samples = 0;
  for (auto _ : state) {
    fitness.Sample(simulation, dt);
    // A script's budget is per parameter set: start a new set before it could run out (outside nothing costly).
    if (++samples % 100000 == 0) fitness.Start(simulation);
  }
  benchmark::DoNotOptimize(fitness.fitness());
}

// Steps the standing robot on MuJoCo; with a term, a FitnessFunction of that one term samples after every step.
void StandingSteps(benchmark::State& state, const std::string& kind) {
  scene::Simulation simulation;
  BuildStanding(simulation);
  std::unique_ptr<FitnessFunction> fitness;
  if (!kind.empty()) fitness = std::make_unique<FitnessFunction>(nlohmann::json{{"terms", {Term(kind)}}}, simulation, 0, "bench");
  if (fitness) fitness->Start(simulation);
  const double dt = simulation.StepDuration();
  double sum = 0.0;
  for (auto _ : state) {
    simulation.Step();
    if (fitness) fitness->Sample(simulation, dt);
    if (simulation.steps() == kStepsPerRun) {
      if (fitness) sum += fitness->fitness();
      simulation.Reset(0);
      if (fitness) fitness->Start(simulation);
    }
  }
  benchmark::DoNotOptimize(sum);
}

void BM_StandingStep(benchmark::State& state) { StandingSteps(state, ""); }
void BM_StandingStepDistance(benchmark::State& state) { StandingSteps(state, "distance"); }
void BM_StandingStepDistanceLua(benchmark::State& state) { StandingSteps(state, "distance.lua"); }
void BM_StandingStepEnergy(benchmark::State& state) { StandingSteps(state, "energy"); }
void BM_StandingStepEnergyLua(benchmark::State& state) { StandingSteps(state, "energy.lua"); }

void BM_SampleDistance(benchmark::State& state) { SampleOnly(state, "distance"); }
void BM_SampleDistanceLua(benchmark::State& state) { SampleOnly(state, "distance.lua"); }
void BM_SampleEnergy(benchmark::State& state) { SampleOnly(state, "energy"); }
void BM_SampleEnergyLua(benchmark::State& state) { SampleOnly(state, "energy.lua"); }

BENCHMARK(BM_SampleDistance)->Unit(benchmark::kNanosecond)->Repetitions(5);
BENCHMARK(BM_SampleDistanceLua)->Unit(benchmark::kNanosecond)->Repetitions(5);
BENCHMARK(BM_SampleEnergy)->Unit(benchmark::kNanosecond)->Repetitions(5);
BENCHMARK(BM_SampleEnergyLua)->Unit(benchmark::kNanosecond)->Repetitions(5);
BENCHMARK(BM_StandingStep)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepDistance)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepDistanceLua)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepEnergy)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepEnergyLua)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);

}  // namespace
}  // namespace orcs::fitness

BENCHMARK_MAIN();
