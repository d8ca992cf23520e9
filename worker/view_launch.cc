#include "worker/view_launch.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "net/cli_style.h"

namespace orcs {

int ReplaceWithLiveView(const char* argv0, const std::string& program, const std::vector<std::string>& arguments) {
  std::vector<std::string> all = {"orcs-view", "--live"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  std::vector<char*> pointers;
  for (std::string& argument : all) pointers.push_back(argument.data());
  pointers.push_back(nullptr);

  const std::filesystem::path beside = std::filesystem::path(argv0).parent_path() / "orcs-view";
  if (std::filesystem::path(argv0).has_parent_path()) execv(beside.c_str(), pointers.data());
  execvp("orcs-view", pointers.data());
  std::cerr << program << ": -gui needs orcs-view (beside " << program << " or on PATH): " << std::strerror(errno)
            << "\n";
  return cli::kExitRunFailed;
}

}  // namespace orcs
