#include "worker/cli_style.h"

#include <algorithm>

namespace orcs::cli {

std::vector<std::string> NormaliseSingleDashOptions(int argc, const char* const* argv,
                                                    const std::vector<std::string_view>& long_names) {
  std::vector<std::string> arguments;
  for (int i = 0; i < argc; ++i) {
    const std::string_view argument = argv[i];
    const bool single_dash_long = i > 0 && argument.size() > 2 && argument[0] == '-' && argument[1] != '-' &&
                                  std::find(long_names.begin(), long_names.end(), argument.substr(1)) != long_names.end();
    arguments.push_back(single_dash_long ? "-" + std::string(argument) : std::string(argument));
  }
  return arguments;
}

}  // namespace orcs::cli
