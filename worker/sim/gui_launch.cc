#include "worker/sim/gui_launch.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "net/cli_style.h"

namespace orcs::sim {

int LaunchGui(const char* argv0, const SimOptions& options) {
  std::vector<std::string> arguments = {"orcs-view", "--live"};
  if (!options.environment.empty()) arguments.insert(arguments.end(), {"--env", options.environment});
  for (const std::string& file : options.initial_value_files) arguments.insert(arguments.end(), {"--ival", file});
  for (const std::string& file : options.value_files) arguments.insert(arguments.end(), {"--val", file});
  arguments.insert(arguments.end(), {"--seed", std::to_string(options.seed)});
  if (options.strict) arguments.push_back("--strict");
  std::vector<char*> pointers;
  for (std::string& argument : arguments) pointers.push_back(argument.data());
  pointers.push_back(nullptr);

  const std::filesystem::path beside = std::filesystem::path(argv0).parent_path() / "orcs-view";
  if (std::filesystem::path(argv0).has_parent_path()) execv(beside.c_str(), pointers.data());
  execvp("orcs-view", pointers.data());
  std::cerr << "orcs-sim: -gui needs orcs-view (beside orcs-sim or on PATH): " << std::strerror(errno) << "\n";
  return cli::kExitRunFailed;
}

}  // namespace orcs::sim
