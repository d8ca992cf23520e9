#include "worker/cli_style.h"

#include <algorithm>
#include <iostream>

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

int ParseArguments(CLI::App& app, int argc, const char* const* argv, const std::vector<std::string_view>& long_names,
                   const std::function<void()>& validate) {
  const std::vector<std::string> arguments = NormaliseSingleDashOptions(argc, argv, long_names);
  std::vector<const char*> pointers;
  for (const std::string& argument : arguments) pointers.push_back(argument.c_str());
  try {
    app.parse(static_cast<int>(pointers.size()), pointers.data());
    if (validate) validate();
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::ParseError& error) {
    std::cerr << app.get_name() << ": " << error.what() << " (see " << app.get_name() << " --help)\n";
    return kExitBadInput;
  }
  return -1;
}

}  // namespace orcs::cli
