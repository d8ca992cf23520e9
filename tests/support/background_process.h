// Runs a program in the background for as long as a test needs it — a broker the test talks to over sockets —
// reading its stdout line by line, signalling it, and collecting its exit status. RunProcess (process.h) is for
// programs that run to completion.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/process.h"

namespace orcs::test_support {

/// A child process with stdout and stderr piped to the test and stdin from /dev/null. The destructor kills it
/// (SIGKILL; its whole group with own_process_group) if it still runs and reaps it, so no test leaves a process
/// behind.
class BackgroundProcess {
 public:
  /// Starts `argv` (argv[0] is the program's path; no PATH search, no shell). Throws std::runtime_error when it
  /// cannot be started. `own_process_group`: the process leads a new process group, as a shell starts a job in
  /// the foreground, so that SignalGroup() reaches it and every child left in its group — a terminal's Ctrl-C.
  explicit BackgroundProcess(const std::vector<std::string>& argv, bool own_process_group = false);
  ~BackgroundProcess();
  BackgroundProcess(const BackgroundProcess&) = delete;
  BackgroundProcess& operator=(const BackgroundProcess&) = delete;

  pid_t pid() const { return pid_; }

  /// The next line the process writes to stdout, without its newline; nullopt when none is complete within
  /// `timeout` or stdout is closed.
  std::optional<std::string> ReadLine(std::chrono::milliseconds timeout);

  /// Sends `signal` to the process (nothing when it has been reaped already).
  void Signal(int signal);

  /// Sends `signal` to the process's whole group, as a terminal's ^C does (kill(-pgid)): only with
  /// own_process_group, and not once the process has been reaped.
  void SignalGroup(int signal);

  /// Waits up to `timeout` for the process to end. Its result holds the exit status, the stdout not yet returned
  /// by ReadLine, and all of stderr; nullopt when it still runs.
  std::optional<ProcessResult> Wait(std::chrono::milliseconds timeout);

  /// Everything the process has written to stderr so far (read without waiting).
  const std::string& err();

 private:
  // Moves whatever the pipes hold into out_ and err_, waiting up to `timeout_ms` for something to arrive.
  void Pump(int timeout_ms);

  pid_t pid_ = -1;
  bool own_group_ = false;
  int out_fd_ = -1;
  int err_fd_ = -1;
  std::string out_;                      ///< stdout read and not yet returned by ReadLine
  std::string err_;                      ///< stderr read so far
  std::optional<ProcessResult> result_;  ///< once reaped
};

}  // namespace orcs::test_support
