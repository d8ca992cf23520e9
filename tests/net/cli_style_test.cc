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

namespace orcs::cli {
namespace {

// A newcomer's paper cuts (issue 52): a mistyped option got no "did you mean", and an error inside a subcommand sent
// the user to the program's help instead of the subcommand's.
struct TwoCommands {
  CLI::App app{"a program", "prog"};
  int jobs = 1;
  std::string scenario;
  std::string out;
  TwoCommands() {
    app.require_subcommand(0, 1);
    CLI::App* sweep = app.add_subcommand("sweep", "a sweep");
    sweep->add_option("scenario", scenario)->required();
    sweep->add_option("--jobs", jobs);
    sweep->add_option("--out", out)->required();
  }
  // The line a failed parse prints, "" when it parsed.
  std::string ErrorOf(std::vector<std::string> words) {
    words.insert(words.begin(), "prog");
    std::vector<const char*> argv;
    for (const std::string& w : words) argv.push_back(w.c_str());
    try {
      app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::ParseError& error) {
      return ParseErrorLine(app, error, words);
    }
    return "";
  }
};

TEST(CliStyleTest, AMistypedOptionIsAnsweredWithTheNearestOne) {
  EXPECT_THAT(TwoCommands().ErrorOf({"sweep", "s.json", "--out", "x", "--job", "3"}),
              ::testing::HasSubstr("did you mean --jobs?"));
  EXPECT_THAT(TwoCommands().ErrorOf({"sweep", "s.json", "--out", "x", "--jbos", "3"}),
              ::testing::HasSubstr("did you mean --jobs?"));
  EXPECT_THAT(TwoCommands().ErrorOf({"sweep", "s.json", "--out", "x", "--quantum", "3"}),
              ::testing::Not(::testing::HasSubstr("did you mean"))) << "nothing near: no guess";
}

TEST(CliStyleTest, AnErrorInsideASubcommandPointsToItsOwnHelp) {
  const std::string missing = TwoCommands().ErrorOf({"sweep", "s.json"});
  EXPECT_THAT(missing, ::testing::HasSubstr("--out"));
  EXPECT_THAT(missing, ::testing::EndsWith("(see prog sweep --help)"));
  EXPECT_EQ(TwoCommands().ErrorOf({"sweep", "s.json", "--out", "x"}), "") << "a good line parses";
}

TEST(CliStyleTest, NearestOptionIsEmptyForAFarName) {
  TwoCommands commands;
  const CLI::App& sweep = *commands.app.get_subcommand("sweep");
  EXPECT_EQ(NearestOption(sweep, "job"), "--jobs");
  EXPECT_EQ(NearestOption(sweep, "ot"), "--out");
  EXPECT_EQ(NearestOption(sweep, "scenery-size"), "");
}

}  // namespace
}  // namespace orcs::cli
