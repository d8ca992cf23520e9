// Runs a program as a child process and captures what it prints: for tests of the command-line programs,
// which must run the real binaries (exit codes, stderr lines, no crash on bad input).
#pragma once

#include <string>
#include <vector>

namespace orcs::test_support {

/// How a child process ended and what it printed.
struct ProcessResult {
  int exit_code = -1;  ///< exit status when the process exited normally, else -1
  int signal = 0;      ///< number of the signal that killed it, 0 when it exited normally
  std::string out;     ///< everything it wrote to stdout
  std::string err;     ///< everything it wrote to stderr
};

/// Runs `argv` (argv[0] is the program's path; no PATH search, no shell) with stdin from /dev/null, waits for
/// it to end and returns its exit status and output. Throws std::runtime_error when it cannot be started.
ProcessResult RunProcess(const std::vector<std::string>& argv);

}  // namespace orcs::test_support
