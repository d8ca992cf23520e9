// orcs-batch's command line (clients/batch/batch_options.h): the `--resume DIR` command printed after a Ctrl-C
// repeats the command and the how-to-run options given, never the job options the folder keeps.
#include "clients/batch/batch_options.h"

#include <gtest/gtest.h>

#include <string>

#include "clients/runtime/interrupt.h"

namespace orcs::batch {
namespace {

using runtime::ShellCommand;

TEST(BatchOptionsTest, TheResumeCommandHasTheCommandTheFolderAndOnlyTheHowOptionsGiven) {
  BatchOptions options;
  options.command = Command::kSweep;
  options.jobs = 9;  // from the folder: never repeated
  options.given = {"--jobs"};
  EXPECT_EQ(ShellCommand(ResumeCommandLine(options, "runs/x")), "orcs-batch sweep --resume runs/x");
  options.command = Command::kSubmit;
  options.broker = "tcp://127.0.0.1:5555";
  options.workers = 3;
  options.given = {"--workers"};
  options.curve_keys = "keys";
  EXPECT_EQ(ShellCommand(ResumeCommandLine(options, "runs/x")),
            "orcs-batch submit --resume runs/x --broker tcp://127.0.0.1:5555 --workers 3 --curve-keys keys");
  options = BatchOptions{};
  options.command = Command::kEvolve;
  options.heartbeat_seconds = 0.25;
  options.given = {"--heartbeat"};
  EXPECT_EQ(ShellCommand(ResumeCommandLine(options, "e")), "orcs-batch evolve --resume e --heartbeat 0.25");
}

}  // namespace
}  // namespace orcs::batch
