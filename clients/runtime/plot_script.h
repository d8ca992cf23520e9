// Draws a picture with one of scripts/plot_*.py (Debian's /usr/bin/python3 with matplotlib), for the commands that
// end with a plot (evolve's fitness.png, compare's compare.png). A missing Python or script costs only the picture.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace orcs::runtime {

/// Runs `/usr/bin/python3 SCRIPTS_DIR/<script> <arguments...>` and waits. Returns false — having said on `out`
/// what to run by hand — when Python or the script is missing or the script fails.
bool RunPlotScript(const std::string& script, const std::vector<std::string>& arguments, std::ostream& out);

}  // namespace orcs::runtime
