// clients/runtime/interrupt.h on its own: how commands are quoted for a shell, and what one and two SIGINTs do in a process
// of their own (a forked child, so that this test's process keeps its handlers). The whole programs under a
// terminal's Ctrl-C are tests/integration/ctrl_c_test.cc.
#include "clients/runtime/interrupt.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

namespace orcs::runtime {
namespace {

TEST(InterruptTest, ShellCommandQuotesOnlyWhatAShellWouldSplitOrExpand) {
  EXPECT_EQ(ShellCommand({"orcs-batch", "run", "--resume", "runs/a-b_c.d"}), "orcs-batch run --resume runs/a-b_c.d");
  EXPECT_EQ(ShellCommand({"orcs-batch", "run", "--resume", "my runs/x"}), "orcs-batch run --resume 'my runs/x'");
  EXPECT_EQ(ShellCommand({"a", "it's", "$HOME", ""}), "a 'it'\\''s' '$HOME' ''");
}

// Waits (bounded) for `pid`; its wait status, or -1 when it did not end within `seconds`.
int WaitFor(pid_t pid, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    const pid_t reaped = waitpid(pid, &status, WNOHANG);
    if (reaped == pid) return status;
    if (reaped < 0 && errno != EINTR) return -1;
    usleep(5000);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

TEST(InterruptTest, OneSignalSetsTheFlagASecondKillsTheWorkerGroupsAndExits130) {
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // a command: one "worker" in a group of its own, then Ctrl-C twice
    CatchInterrupts();
    SetInterruptHint("continue with: orcs-batch run --resume x");
    const pid_t worker = fork();
    if (worker == 0) {
      setpgid(0, 0);
      pause();
      _exit(0);
    }
    setpgid(worker, worker);
    AddWorkerGroup(worker);
    [[maybe_unused]] const ssize_t sent = write(pipe_fds[1], &worker, sizeof worker);
    kill(getpid(), SIGINT);
    if (!InterruptRequested()) _exit(3);  // the first only sets the flag
    kill(getpid(), SIGINT);
    _exit(4);  // not reached: the second exits 130
  }
  close(pipe_fds[1]);
  pid_t worker = 0;
  ASSERT_EQ(read(pipe_fds[0], &worker, sizeof worker), static_cast<ssize_t>(sizeof worker));
  close(pipe_fds[0]);
  const int status = WaitFor(child, 10.0);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), kExitInterrupted);
  // The worker, now this process's orphan's child, was killed: its group is gone (ESRCH) once init reaps it.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  bool gone = false;
  while (!gone && std::chrono::steady_clock::now() < deadline) {
    const std::string stat = "/proc/" + std::to_string(worker) + "/stat";
    FILE* file = fopen(stat.c_str(), "r");
    if (file == nullptr) {
      gone = true;
      break;
    }
    char buffer[512] = {};
    const std::size_t n = fread(buffer, 1, sizeof buffer - 1, file);
    fclose(file);
    const std::string text(buffer, n);
    const std::size_t close_paren = text.rfind(')');
    gone = close_paren != std::string::npos && close_paren + 2 < text.size() && text[close_paren + 2] == 'Z';
    if (!gone) usleep(5000);
  }
  EXPECT_TRUE(gone) << "the worker group outlived the second signal";
}

}  // namespace
}  // namespace orcs::runtime
