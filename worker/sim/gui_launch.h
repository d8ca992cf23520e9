// orcs-sim -gui: the original's GUI. The simulator itself stays headless; -gui hands the same world (-env, -ival,
// -val) to orcs-view's live mode (docs/viewer.md), which serves the GUI to a browser.
#pragma once

#include "worker/sim/sim_options.h"

namespace orcs::sim {

/// Replaces this process with `orcs-view --live` (found beside `argv0`, else on PATH) for the options' world.
/// Returns only when that fails, with the exit code to use (after printing one line).
int LaunchGui(const char* argv0, const SimOptions& options);

}  // namespace orcs::sim
