#include "tests/support/background_process.h"

#include <gtest/gtest.h>

#include <csignal>
#include <stdexcept>

namespace orcs::test_support {
namespace {

using std::chrono::milliseconds;

TEST(BackgroundProcess, ReadsLinesWhileTheProcessRuns) {
  BackgroundProcess process({"/bin/sh", "-c", "echo first; echo second; exec sleep 30"});
  EXPECT_EQ(process.ReadLine(milliseconds(5000)), "first");
  EXPECT_EQ(process.ReadLine(milliseconds(5000)), "second");
  EXPECT_EQ(process.ReadLine(milliseconds(50)), std::nullopt);  // sleeping: no third line
  EXPECT_EQ(process.Wait(milliseconds(0)), std::nullopt);
}

TEST(BackgroundProcess, SignalEndsTheProcessAndWaitReportsIt) {
  BackgroundProcess process({"/bin/sh", "-c", "echo up; exec sleep 30"});
  ASSERT_EQ(process.ReadLine(milliseconds(5000)), "up");
  process.Signal(SIGTERM);
  const std::optional<ProcessResult> result = process.Wait(milliseconds(5000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->signal, SIGTERM);
  EXPECT_EQ(result->exit_code, -1);
}

TEST(BackgroundProcess, WaitCollectsExitCodeAndOutput) {
  BackgroundProcess process({"/bin/sh", "-c", "echo out; echo err >&2; exit 3"});
  const std::optional<ProcessResult> result = process.Wait(milliseconds(5000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->exit_code, 3);
  EXPECT_EQ(result->signal, 0);
  EXPECT_EQ(result->out, "out\n");
  EXPECT_EQ(result->err, "err\n");
  EXPECT_EQ(process.Wait(milliseconds(0))->exit_code, 3);  // asking again gives the same answer
}

TEST(BackgroundProcess, DestructorKillsARunningProcess) {
  pid_t pid = -1;
  {
    BackgroundProcess process({"/bin/sh", "-c", "exec sleep 30"});
    pid = process.pid();
    ASSERT_GT(pid, 0);
  }
  EXPECT_NE(::kill(pid, 0), 0);  // reaped: no such process any more
}

TEST(BackgroundProcess, MissingProgramThrows) {
  EXPECT_THROW(BackgroundProcess({"/nonexistent/program"}), std::runtime_error);
}

}  // namespace
}  // namespace orcs::test_support
