// The cost of crash isolation per job (docs/benchmarks.md, "Crash isolation"): the same job run in-process with
// RunJob and through SimulationSandbox, whose simulation process is the real `orcs-worker --sandbox-child`. Wall
// time (UseRealTime: the work happens in the other process).
//   BM_*/0  a job with a scenario that does not parse: no simulation, so the time is the round trip itself —
//           serialise the job, the socket pair both ways, parse it, the INVALID_INPUT result back
//   BM_*/1  a short A-Series job: 0.2 s simulated, one parameter set (as in tests/integration/worker_faults_test.cc)
//   BM_NewProcess  starting a simulation process and its first (non-simulating) job: the extra cost of a crash
//
//   sandbox_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//                 --benchmark_enable_random_interleaving=true
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "worker/job/job_translation.h"
#include "worker/job/simulation_sandbox.h"

namespace orcs::worker {
namespace {

v1::Job BenchJob(bool simulate) {
  v1::Job job;
  job.set_job_id("bench");
  job.set_batch_id("bench");
  job.set_scenario_json(simulate ? nlohmann::json::parse(R"({
      "duration": 0.2,
      "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
      "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]}})")
                                       .dump()
                                 : std::string("{not json"));
  job.set_genome_json("[20, 1.5, 0, 0, 20, 1.5, 3, 0]");
  job.set_seed(3);
  job.set_time_limit_seconds(60);
  return job;
}

void Check(const v1::Result& result, bool simulate, benchmark::State& state) {
  const v1::Result::Status expected = simulate ? v1::Result::OK : v1::Result::INVALID_INPUT;
  if (result.status() != expected) state.SkipWithError(("unexpected result: " + result.message()).c_str());
}

void BM_InProcess(benchmark::State& state) {
  const bool simulate = state.range(0) != 0;
  const v1::Job job = BenchJob(simulate);
  for (auto _ : state) {
    const v1::Result result = RunJob(job);
    Check(result, simulate, state);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Sandboxed(benchmark::State& state) {
  const bool simulate = state.range(0) != 0;
  const v1::Job job = BenchJob(simulate);
  SimulationSandbox sandbox({ORCS_BINARY_DIR "/bin/orcs-worker", "--sandbox-child"});
  sandbox.Run(job);  // the process's first job pays for loading the program: not part of the per-job cost
  for (auto _ : state) {
    const v1::Result result = sandbox.Run(job);
    Check(result, simulate, state);
  }
  state.SetItemsProcessed(state.iterations());
}

// What a crash costs on top of the lost job: a new simulation process, started and answering its first job.
void BM_NewProcess(benchmark::State& state) {
  const v1::Job job = BenchJob(false);
  for (auto _ : state) {
    SimulationSandbox sandbox({ORCS_BINARY_DIR "/bin/orcs-worker", "--sandbox-child"});
    Check(sandbox.Run(job), false, state);
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_NewProcess)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_InProcess)->Arg(0)->Arg(1)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Sandboxed)->Arg(0)->Arg(1)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace orcs::worker

BENCHMARK_MAIN();
