// Ctrl-C for every client command — orcs-batch run, submit, sweep, evolve and regress, and orcs-gap (issue 47,
// docs/batch.md "Ctrl-C"). One place for what they share:
//  - SIGINT and SIGTERM (a terminal's ^C reaches the whole foreground process group; Slurm's time limit sends
//    SIGTERM) set one flag. The loops that wait for results look at it between their bounded waits
//    (BatchClient::Next with a timeout) and stop: a batch keeps what arrived, a generation or fit under way is
//    abandoned (JobRunner::Run throws Interrupted). The command then writes progress.json "interrupted", prints how
//    to resume and exits kExitInterrupted; the local workers, which are in their own process groups and so never
//    see the terminal's ^C, are stopped by their parent (LocalCluster).
//  - A second signal does not wait for any of that: it kills the registered local worker process groups
//    (SIGKILL), writes the resume hint to stderr and exits kExitInterrupted at once, from the signal handler. What
//    is on disk stays resumable: every output file is written to a temporary name and renamed, and the one file
//    appended to (results.jsonl.partial) loses at most a cut last line, which --resume drops and runs again.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

namespace orcs::runtime {

/// Exit code of a command stopped by Ctrl-C or SIGTERM: the shell's 128 + SIGINT.
inline constexpr int kExitInterrupted = 130;

/// Thrown out of a wait for results once the command is interrupted: unwinds the step under way (a generation,
/// a fit), whose results are dropped.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted (Ctrl-C or SIGTERM)") {}
};

/// Catches SIGINT and SIGTERM for the rest of the process (see above). Idempotent.
void CatchInterrupts();

/// The flag the first signal sets: for loops that take a `const std::atomic<bool>*` stop (SessionOptions::stop,
/// RunnerOptions::stop).
const std::atomic<bool>& InterruptFlag();
/// Whether the command has been interrupted.
inline bool InterruptRequested() { return InterruptFlag().load(); }

/// What a second Ctrl-C writes to stderr before it exits, e.g. "orcs-batch: stopped at once; continue with:
/// orcs-batch run --resume runs/x". Set before the command's work starts; at most 1 KiB is kept.
void SetInterruptHint(const std::string& line);

/// A local worker's process group (its pid: LocalCluster starts each worker as the leader of its own group), which
/// a second signal kills with SIGKILL; removed once the worker is reaped. At most 4096 at once (more are not
/// killed by a second signal, only by their parent's ending: PR_SET_PDEATHSIG).
void AddWorkerGroup(pid_t group);
void RemoveWorkerGroup(pid_t group);

/// `words` as a shell command line to copy: each word single-quoted when it holds anything but letters, digits
/// and -_./=:@%+,
std::string ShellCommand(const std::vector<std::string>& words);

/// For tests of the code that reacts (a loop that polls the flag): sets or clears the flag as a signal would.
void SetInterruptForTest(bool interrupted);

}  // namespace orcs::runtime
