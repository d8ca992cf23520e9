// `orcs-batch evolve SCENARIO.json [--generations G] [--population P] [--algorithm NAME] [--seed S] [--validate N]
//  [--out DIR | --resume DIR] [--workers N | --broker ENDPOINT]` (docs/evolution.md): evolves the scenario's
// genome with a pagmo2 algorithm, every generation one batch through the broker (an embedded one with local
// workers, or a running one), every genome under the scenario's randomised parameter sets. Writes DIR/checkpoint.json,
// fitness.csv (and fitness.png), best_genome.json after every generation, and at the end DIR/best/: the winner's
// run with its logs, replayed from its genome, and its runs on `validate` fresh seeds.
#pragma once

#include <atomic>

#include "clients/batch/batch_options.h"

namespace orcs::evolve {

/// Runs the command. Exit 0 when the run finished (or had nothing left to do), 1 when the winner did not replay to
/// its fitness, runtime::kExitInterrupted when `stop` was set (Ctrl-C: clients/runtime/interrupt.h, whose handlers the
/// caller installs): the generation under way is abandoned and the resume command printed. Throws InputError for bad input (before anything is submitted),
/// runtime::BatchClientError when the broker is lost.
int RunEvolve(const batch::BatchOptions& options, const std::atomic<bool>* stop);

}  // namespace orcs::evolve
