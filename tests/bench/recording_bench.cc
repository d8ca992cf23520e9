// The cost of recording (docs/recording.md): the default A-Series standing run, one step per iteration, with and
// without a Recorder sampling after every step, in the same process. docs/benchmarks.md records the ratio and the
// file size; the bound is at most 10 % slower.
#include <benchmark/benchmark.h>

#include <memory>

#include "model/evaluation/recorder.h"
#include "model/scene/world_setup.h"

namespace orcs::evaluation {
namespace {

constexpr int kStepsPerRun = 1000;  // 10 s at 10 ms: the run docs/benchmarks.md quotes

// Steps the standing robot, restarting every kStepsPerRun steps; with `record`, a recorder samples each step and
// a finished run's bytes are counted.
void StandingSteps(benchmark::State& state, bool record) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  std::unique_ptr<Recorder> recorder;
  if (record) recorder = std::make_unique<Recorder>(simulation, RecordingSource{});
  std::size_t bytes = 0;
  int runs = 0;
  for (auto _ : state) {
    simulation.Step();
    if (recorder) recorder->Sample();
    if (simulation.steps() == kStepsPerRun) {
      if (recorder) {
        bytes += recorder->Finish().size();
        ++runs;
      }
      simulation.Reset(0);
      if (record) recorder = std::make_unique<Recorder>(simulation, RecordingSource{});
    }
  }
  if (runs > 0) state.counters["file_MB_per_10s"] = static_cast<double>(bytes) / runs / 1e6;
}

void BM_StandingStep(benchmark::State& state) { StandingSteps(state, false); }
void BM_StandingStepRecorded(benchmark::State& state) { StandingSteps(state, true); }

// The recorder alone: one frame of the standing robot (461 channels) read, XOR-ed and deflated.
void BM_RecorderSample(benchmark::State& state) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  simulation.Step();
  Recorder recorder(simulation, RecordingSource{});
  for (auto _ : state) recorder.Sample();
}

BENCHMARK(BM_RecorderSample)->Unit(benchmark::kMicrosecond)->Repetitions(5);
BENCHMARK(BM_StandingStep)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);
BENCHMARK(BM_StandingStepRecorded)->Unit(benchmark::kMicrosecond)->Iterations(5000)->Repetitions(5);

}  // namespace
}  // namespace orcs::evaluation

BENCHMARK_MAIN();
