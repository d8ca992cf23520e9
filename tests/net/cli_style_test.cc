#include "net/cli_style.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

namespace orcs::cli {
namespace {

using ::testing::ElementsAre;

const std::vector<std::string_view> kLongNames{"env", "val", "ival"};

std::vector<std::string> Normalise(const std::vector<const char*>& argv) {
  return NormaliseSingleDashOptions(static_cast<int>(argv.size()), argv.data(), kLongNames);
}

TEST(CliStyleTest, RewritesSingleDashLongOptions) {
  EXPECT_THAT(Normalise({"orcs-sim", "-env", "a.xml", "-val", "b.val", "-ival", "c.val"}),
              ElementsAre("orcs-sim", "--env", "a.xml", "--val", "b.val", "--ival", "c.val"));
}

TEST(CliStyleTest, LeavesEverythingElseAlone) {
  EXPECT_THAT(Normalise({"orcs-sim", "-5", "--x", "-foo", "--env", "-e", "-", "--", "env", "-env=a.xml", "-Env",
                         "-envx", "-va"}),
              ElementsAre("orcs-sim", "-5", "--x", "-foo", "--env", "-e", "-", "--", "env", "-env=a.xml", "-Env",
                          "-envx", "-va"));
}

TEST(CliStyleTest, NeverTouchesTheProgramName) {
  EXPECT_THAT(Normalise({"-env", "-env"}), ElementsAre("-env", "--env"));
}

TEST(CliStyleTest, OnlyTheGivenNames) {
  const std::vector<const char*> argv{"prog", "-env", "-port"};
  EXPECT_THAT(NormaliseSingleDashOptions(3, argv.data(), {"port"}), ElementsAre("prog", "-env", "--port"));
  EXPECT_THAT(NormaliseSingleDashOptions(3, argv.data(), {}), ElementsAre("prog", "-env", "-port"));
}

TEST(CliStyleTest, EmptyCommandLine) {
  EXPECT_TRUE(NormaliseSingleDashOptions(0, nullptr, kLongNames).empty());
  EXPECT_THAT(Normalise({"prog"}), ElementsAre("prog"));
}

TEST(CliStyleTest, ExitCodes) {
  EXPECT_EQ(kExitOk, 0);
  EXPECT_EQ(kExitRunFailed, 1);
  EXPECT_EQ(kExitBadInput, 2);
}

}  // namespace
}  // namespace orcs::cli
