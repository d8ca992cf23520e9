// How every orcs program ends (docs/architecture.md, "Errors and bad input"): its exit codes, and one guard around
// its body so that what escapes it is said the same way by all of them — never a stack trace.
#pragma once

#include <functional>
#include <string_view>

namespace orcs::cli {

/// Exit codes of every orcs program.
constexpr int kExitOk = 0;
constexpr int kExitRunFailed = 1;  ///< the input was fine, the run was not (unstable physics, failed jobs)
constexpr int kExitBadInput = 2;   ///< bad input: one line on stderr names the file, line or field

/// Runs a program's `body` and returns its exit code. What escapes it: an InputError (bad input, and what derives
/// from it: a key file, a broker that does not answer) → "PROGRAM: what" on stderr, kExitBadInput; any other
/// exception → "PROGRAM: internal error: what", kExitRunFailed. A program's own endings (Ctrl-C's 130, a bus error
/// with the torque off) are its body's to catch first.
int RunProgram(std::string_view program, const std::function<int()>& body);

/// The same, after the command line: a `parsed` with an exit_code ≥ 0 (help printed, or the command-line error
/// said) ends the program with it; otherwise `body(parsed.options)` runs under the guard.
template <typename Parsed, typename Body>
int RunProgram(std::string_view program, const Parsed& parsed, Body body) {
  if (parsed.exit_code >= 0) return parsed.exit_code;
  return RunProgram(program, [&] { return body(parsed.options); });
}

}  // namespace orcs::cli
