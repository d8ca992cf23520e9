// The cost of a scripted fitness term (issue 50, docs/extending.md): the standing A-Series on MuJoCo, one step and
// one fitness sample per iteration — no term, the built-in `distance`, the shipped distance.lua (the same value, to
// the bit), the built-in `energy` and energy.lua — in one process. docs/benchmarks.md records each term's cost as a
// share of the bare step; the bound: a scripted term costs at most 5 % of a standing MuJoCo step.
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

// Steps the standing robot on MuJoCo; with a term, a FitnessFunction of that one term samples after every step.
void StandingSteps(benchmark::State& state, const std::string& kind) {
  scene::Simulation simulation;
  simulation.repository().Set("/Simulation/Engine", "MuJoCo");
  scene::EnvironmentDescription environment;
  environment.agents.push_back(scene::AgentDescription{});
  simulation.LoadEnvironment(environment);
  simulation.Build();
  simulation.SetExcludedCollisionEvents(false);  // as a batch job runs it
  std::unique_ptr<FitnessFunction> fitness;
  if (!kind.empty()) fitness = std::make_unique<FitnessFunction>(nlohmann::json{{"terms", {Term(kind)}}}, simulation, 0, "bench");
  simulation.Reset(0);
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

BENCHMARK(BM_StandingStep)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepDistance)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepDistanceLua)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepEnergy)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepEnergyLua)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);

}  // namespace
}  // namespace orcs::fitness

BENCHMARK_MAIN();
