// Every fuzz target's seeds and its recorded regressions (tests/fuzz/regressions/<target>/, inputs that once
// crashed or hung) through the same entry functions the libFuzzer targets call, in the ordinary build: seeds must be
// accepted; a regression may be rejected, but only with a documented error of one line, and must return.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "orcs/v1/broker.pb.h"
#include "tests/fuzz/fuzz_entries.h"
#include "tests/fuzz/fuzz_seeds.h"

namespace orcs::fuzz {

// Test listings and failure messages show the target's name (found by argument-dependent lookup).
void PrintTo(const FuzzTarget& target, std::ostream* out) { *out << target.name; }

namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

class FuzzRegressionTest : public testing::TestWithParam<FuzzTarget> {};

TEST_P(FuzzRegressionTest, SeedsAreAccepted) {
  const std::vector<Seed> seeds = SeedsFor(GetParam().name, ORCS_SOURCE_DIR);
  ASSERT_FALSE(seeds.empty());
  for (const Seed& seed : seeds) {
    const FeedResult result = GetParam().feed(seed.bytes);
    EXPECT_TRUE(result.accepted) << seed.name << ": " << result.error;
  }
}

TEST_P(FuzzRegressionTest, RegressionsReturnWithAOneLineErrorOrAccepted) {
  const fs::path dir = fs::path(ORCS_SOURCE_DIR) / "tests/fuzz/regressions" / GetParam().name;
  if (!fs::exists(dir)) GTEST_SKIP() << "no regressions recorded for " << GetParam().name;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    const FeedResult result = GetParam().feed(ReadBytes(entry.path()));
    if (!result.accepted) {
      EXPECT_FALSE(result.error.empty());
      EXPECT_EQ(result.error.find('\n'), std::string::npos) << result.error;
    }
  }
}

// Rejections name what is wrong: a broken value file line and an unknown OSP command, as the docs promise.
TEST(FuzzEntriesTest, RejectionsCarryTheReadersMessages) {
  EXPECT_EQ(FeedValueFile("/Simulation/TimeStepSize\n").error.find("expected 'path=value'") != std::string::npos,
            true);
  const FeedResult unknown = FeedOspDatagrams(JoinDatagrams({std::string("\x01\xff", 2)}));
  EXPECT_FALSE(unknown.accepted);
  EXPECT_EQ(unknown.error, "1 datagrams ignored");
}

// A JOB reaches the job translation: the oscillator job's seed with a genome of the wrong length is refused with
// the genome check's message, which only CheckRequest gives.
TEST(FuzzEntriesTest, AJobIsTranslatedAndChecked) {
  for (const Seed& seed : SeedsFor("broker_message", ORCS_SOURCE_DIR)) {
    if (seed.name != "broker_job_oscillator.pb") continue;
    v1::BrokerToWorker message;
    ASSERT_TRUE(message.ParseFromString(seed.bytes.substr(1)));
    message.mutable_job()->set_genome_json("[1, 2]");
    const FeedResult result = FeedBrokerMessage(std::string(1, '\x02') + message.SerializeAsString());
    EXPECT_FALSE(result.accepted);
    EXPECT_NE(result.error.find("genome"), std::string::npos) << result.error;
    return;
  }
  FAIL() << "no seed broker_job_oscillator.pb";
}

TEST(FuzzEntriesTest, SplitDatagramsInvertsJoinAndKeepsAShortTail) {
  const std::vector<std::string> datagrams = {"", "abc", std::string(300, 'x')};
  EXPECT_EQ(SplitDatagrams(JoinDatagrams(datagrams)), datagrams);
  EXPECT_EQ(SplitDatagrams(std::string("\x05\x00" "ab", 4)), std::vector<std::string>{"ab"});
  EXPECT_TRUE(SplitDatagrams("\x05").empty());
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzRegressionTest, testing::ValuesIn(FuzzTargets()),
                         [](const testing::TestParamInfo<FuzzTarget>& target) { return std::string(target.param.name); });

}  // namespace
}  // namespace orcs::fuzz
