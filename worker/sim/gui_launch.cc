#include "worker/sim/gui_launch.h"

#include <string>
#include <vector>

#include "worker/view_launch.h"

namespace orcs::sim {

int LaunchGui(const char* argv0, const SimOptions& options) {
  std::vector<std::string> arguments;
  if (!options.environment.empty()) arguments.insert(arguments.end(), {"--env", options.environment});
  for (const std::string& file : options.initial_value_files) arguments.insert(arguments.end(), {"--ival", file});
  for (const std::string& file : options.value_files) arguments.insert(arguments.end(), {"--val", file});
  arguments.insert(arguments.end(), {"--seed", std::to_string(options.seed)});
  if (options.strict) arguments.push_back("--strict");
  return ReplaceWithLiveView(argv0, "orcs-sim", arguments);
}

}  // namespace orcs::sim
