// `orcs-sim --scenario FILE.json [--genome JSON] [--seed S]`: one job evaluated in this process exactly as a worker
// evaluates it (worker/evaluation), its result printed as one results.jsonl line. So a job from a batch — the
// winner of an evolution, a failed regression case — replays on a laptop to the same bits.
#pragma once

#include "worker/sim/sim_options.h"

namespace orcs::sim {

/// Evaluates the job and prints its result line on stdout. Returns the exit code: 0 ok, 1 when the job did not
/// end ok (unstable physics, timeout); throws InputError for bad input (exit 2).
int RunScenario(const SimOptions& options);

}  // namespace orcs::sim
