// Command-line conventions shared by the orcs programs.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::cli {

/// The original simulator took single-dash long options (-env, -val, -ival, -play, -port); CLI11 reads them
/// as "--env" etc. Rewrites every argument that is exactly "-<name>" for a name in `long_names` to "--<name>".
std::vector<std::string> NormaliseSingleDashOptions(int argc, const char* const* argv,
                                                    const std::vector<std::string_view>& long_names);

/// Parses argv into `app`, accepting the single-dash spellings of `long_names`. Returns -1 when the program goes
/// on; kExitOk after printing --help; kExitBadInput after printing one line "NAME: what (see NAME --help)" to
/// stderr, NAME being the app's name. `validate`, when given, runs after parsing and may throw CLI::Error too.
int ParseArguments(CLI::App& app, int argc, const char* const* argv, const std::vector<std::string_view>& long_names,
                   const std::function<void()>& validate = {});

/// A number from `min` to `max`. Unlike CLI::Range it refuses NaN ("--time-limit nan" passes every comparison),
/// and "inf" where the range is finite; the message names what was expected and what was found.
CLI::Validator NumberIn(double min, double max);

/// A seed: decimal digits only, 0 … `max` (default 2^64−1). CLI11 alone reads "--seed -1" as 2^64−1 and
/// "--seed 1e23" as a number; both are refused with one line.
CLI::Validator Seed(std::uint64_t max = UINT64_MAX);

/// A ZeroMQ endpoint to connect to: tcp://HOST:PORT (PORT 1…65535; HOST a name, an IPv4 address or [IPv6]),
/// ipc://PATH or inproc://NAME. "--broker nonsense" is bad input (exit 2), found before anything starts.
CLI::Validator Endpoint();

/// Exit codes of every orcs program.
constexpr int kExitOk = 0;
constexpr int kExitRunFailed = 1;  ///< the input was fine, the run was not (unstable physics, failed jobs)
constexpr int kExitBadInput = 2;   ///< bad input: one line on stderr names the file, line or field

}  // namespace orcs::cli
