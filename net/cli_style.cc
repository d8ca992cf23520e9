#include "net/cli_style.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "base/near_names.h"

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

namespace {

// The (sub)command the command line reached: "orcs-batch sweep" for an error inside sweep's options.
const CLI::App& ActiveCommand(const CLI::App& app, std::string& name) {
  name = app.get_name();
  const CLI::App* at = &app;
  for (std::vector<CLI::App*> chosen = at->get_subcommands(); !chosen.empty(); chosen = at->get_subcommands()) {
    at = chosen.back();
    name += " " + at->get_name();
  }
  return *at;
}

}  // namespace

std::string NearestOption(const CLI::App& command, std::string_view mistyped) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back(name);
  }
  const std::vector<std::string> near = NearNames(mistyped, names, 1);
  return near.empty() ? "" : "--" + near.front();
}

std::string ParseErrorLine(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& arguments) {
  std::string name;
  const CLI::App& command = ActiveCommand(app, name);
  std::string hint;
  // An option the command does not have ("--job 3"): the nearest one it has.
  for (std::size_t i = 1; i < arguments.size() && hint.empty(); ++i) {
    const std::string& argument = arguments[i];
    if (!argument.starts_with("--") || argument.size() < 3) continue;
    const std::string mistyped = argument.substr(2, argument.find('=') - 2);
    bool known = false;
    for (const CLI::Option* option : command.get_options()) known = known || option->check_lname(mistyped);
    for (const CLI::Option* option : app.get_options()) known = known || option->check_lname(mistyped);
    if (known) continue;
    const std::string nearest = NearestOption(command, mistyped);
    if (!nearest.empty()) hint = "; did you mean " + nearest + "?";
  }
  return app.get_name() + ": " + error.what() + hint + " (see " + name + " --help)";
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
    std::cerr << ParseErrorLine(app, error, arguments) << "\n";
    return kExitBadInput;
  }
  return -1;
}

namespace {

// "0.001", "1e+07", "inf": a bound for messages.
std::string Bound(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

CLI::Validator NumberIn(double min, double max) {
  const std::string expected = "a number from " + Bound(min) + " to " + Bound(max);
  return CLI::Validator(
      [min, max, expected](const std::string& text) -> std::string {
        double number = 0.0;
        const char* begin = text.data();
        const char* end = text.data() + text.size();
        if (begin != end && *begin == '+') ++begin;
        const auto [stop, error] = std::from_chars(begin, end, number);
        if (error != std::errc() || stop != end || std::isnan(number) || number < min || number > max) {
          return "expected " + expected + ", found '" + text + "'";
        }
        return "";
      },
      "NUMBER in [" + Bound(min) + ", " + Bound(max) + "]");
}

CLI::Validator Seed(std::uint64_t max) {
  return CLI::Validator(
      [max](const std::string& text) -> std::string {
        std::uint64_t seed = 0;
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        const auto [stop, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
        if (!digits || error != std::errc() || stop != text.data() + text.size() || seed > max) {
          return "expected a seed, an integer from 0 to " + std::to_string(max) + ", found '" + text + "'";
        }
        return "";
      },
      "SEED");
}

CLI::Validator Endpoint() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        const std::string expected =
            "expected an endpoint tcp://HOST:PORT (e.g. tcp://127.0.0.1:5555), ipc://PATH or inproc://NAME, found '" +
            text + "'";
        for (const char* scheme : {"ipc://", "inproc://"}) {
          if (text.starts_with(scheme)) return text.size() > std::string_view(scheme).size() ? "" : expected;
        }
        if (!text.starts_with("tcp://")) return expected;
        const std::string address = text.substr(6);
        const std::size_t colon = address.rfind(':');
        if (colon == std::string::npos || colon == 0) return expected;
        const std::string host = address.substr(0, colon);
        const std::string port = address.substr(colon + 1);
        if (host.find_first_of(" /\t") != std::string::npos) return expected;
        int number = 0;
        const auto [stop, error] = std::from_chars(port.data(), port.data() + port.size(), number);
        if (port.empty() || error != std::errc() || stop != port.data() + port.size() || number < 1 || number > 65535) {
          return expected + " (the port must be 1…65535)";
        }
        return "";
      },
      "ENDPOINT");
}

}  // namespace orcs::cli
