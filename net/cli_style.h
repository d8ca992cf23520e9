// Command-line conventions shared by the orcs programs.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "base/run_program.h"  // kExitOk, kExitRunFailed, kExitBadInput; RunProgram

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

/// The long option of `command` nearest to `mistyped` (a name without its dashes) — a letter or two off, or a
/// name it begins ("job" → "--jobs") — as "--name"; "" when none is near. For "did you mean" in ParseArguments, whose
/// one line also names the subcommand's own help ("see orcs-batch sweep --help").
std::string NearestOption(const CLI::App& command, std::string_view mistyped);

/// The one line a command-line error prints: "NAME: what[; did you mean --jobs?] (see NAME [SUBCOMMAND] --help)",
/// naming the help of the subcommand the line reached. `arguments` are the command line's words, argv[0] first.
std::string ParseErrorLine(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& arguments);

/// A number from `min` to `max`. Unlike CLI::Range it refuses NaN ("--time-limit nan" passes every comparison),
/// and "inf" where the range is finite; the message names what was expected and what was found.
CLI::Validator NumberIn(double min, double max);

/// A seed: decimal digits only, 0 … `max` (default 2^64−1). CLI11 alone reads "--seed -1" as 2^64−1 and
/// "--seed 1e23" as a number; both are refused with one line.
CLI::Validator Seed(std::uint64_t max = UINT64_MAX);

/// A ZeroMQ endpoint to connect to: tcp://HOST:PORT (PORT 1…65535; HOST a name, an IPv4 address or [IPv6]),
/// ipc://PATH or inproc://NAME. "--broker nonsense" is bad input (exit 2), found before anything starts.
CLI::Validator Endpoint();


}  // namespace orcs::cli
