// The original's -gui switch: the simulators themselves stay headless, and `-gui` hands their world to orcs-view's
// live mode (docs/viewer.md), which serves the GUI to a browser. orcs-sim -gui and orcs-osp -gui both do it here.
#pragma once

#include <string>
#include <vector>

namespace orcs {

/// Replaces this process with `orcs-view --live ARGUMENTS...`, found beside `argv0`, else on PATH. Returns only when
/// that fails, with the exit code to use, after one line on stderr prefixed "PROGRAM: -gui".
int ReplaceWithLiveView(const char* argv0, const std::string& program, const std::vector<std::string>& arguments);

}  // namespace orcs
