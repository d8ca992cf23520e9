// The real orcs-view program: one clear line and exit 2 for every bad input, and the address it serves on.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <regex>

#include "model/evaluation/recorder.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kView = ORCS_BINARY_DIR "/bin/orcs-view";
const std::string kSim = ORCS_BINARY_DIR "/bin/orcs-sim";

class OrcsViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_.Write("web/index.html", "<html></html>");
    dir_.Write("web/files.txt", "index.html -> index.html\n");
    const ProcessResult recorded = RunProcess({kSim, "--duration", "0.2", "--record", dir_.PathOf("run.orcsrec")});
    ASSERT_EQ(recorded.exit_code, 0) << recorded.err;
  }

  ProcessResult View(std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), {kView, "--web-dir", dir_.PathOf("web")});
    return RunProcess(arguments);
  }

  // Expects exit 2 and exactly one line on stderr containing every `parts`.
  void ExpectBadInput(const ProcessResult& result, const std::vector<std::string>& parts) {
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_THAT(result.err, StartsWith("orcs-view: "));
    for (const std::string& part : parts) EXPECT_THAT(result.err, HasSubstr(part));
  }

  std::string RecordingBytes() { return dir_.Read("run.orcsrec"); }

  test_support::TempDir dir_;
};

TEST_F(OrcsViewTest, ATruncatedRecordingIsNamed) {
  const std::string bytes = RecordingBytes();
  const std::string cut = dir_.Write("cut.orcsrec", bytes.substr(0, bytes.size() / 2));
  ExpectBadInput(View({cut}), {cut, "truncated"});
}

TEST_F(OrcsViewTest, AForeignFileIsNamed) {
  const std::string foreign = dir_.Write("notes.orcsrec", "these are my notes\n");
  ExpectBadInput(View({foreign}), {foreign, "not an orcs recording"});
}

TEST_F(OrcsViewTest, ANewerFormatVersionSaysToUpdate) {
  std::string bytes = RecordingBytes();
  const std::uint32_t newer = evaluation::kRecordingVersion + 1;
  std::memcpy(bytes.data() + 8, &newer, sizeof newer);
  const std::string file = dir_.Write("new.orcsrec", bytes);
  ExpectBadInput(View({file}), {file, "is newer than this orcs reads", "update orcs"});
}

TEST_F(OrcsViewTest, AFolderWithNothingViewableIsNamed) {
  dir_.Write("empty/readme.txt", "nothing here");
  ExpectBadInput(View({dir_.PathOf("empty")}), {dir_.PathOf("empty"), "nothing viewable"});
}

TEST_F(OrcsViewTest, AMissingPageNamesFilesTxtAndTheFix) {
  dir_.Write("broken-web/files.txt", "node_modules/three/build/three.module.js -> three.module.js\n");
  const ProcessResult result =
      RunProcess({kView, "--web-dir", dir_.PathOf("broken-web"), dir_.PathOf("run.orcsrec")});
  ExpectBadInput(result, {"files.txt:1", "three.module.js is missing", "scripts/setup.sh"});
}

TEST_F(OrcsViewTest, ServesOnLoopbackAndAPortInUseIsNamed) {
  BackgroundProcess first({kView, "--web-dir", dir_.PathOf("web"), "--port", "0", dir_.PathOf("run.orcsrec")});
  const std::optional<std::string> line = first.ReadLine(std::chrono::seconds(20));
  ASSERT_TRUE(line) << first.err();
  std::smatch match;
  ASSERT_TRUE(std::regex_search(*line, match, std::regex(R"(serving http://127\.0\.0\.1:(\d+)/)"))) << *line;
  const std::string port = match[1];
  ExpectBadInput(View({"--port", port, dir_.PathOf("run.orcsrec")}), {"127.0.0.1:" + port, "--port"});
  first.Signal(SIGTERM);
  const std::optional<ProcessResult> ended = first.Wait(std::chrono::seconds(10));
  ASSERT_TRUE(ended);
  EXPECT_EQ(ended->exit_code, 0) << "SIGTERM stops it cleanly";
}

TEST_F(OrcsViewTest, ABadOptionIsOneLine) {
  ExpectBadInput(View({"--live", dir_.PathOf("run.orcsrec")}), {"--live"});
  ExpectBadInput(View({}), {"give recordings"});
  ExpectBadInput(View({"--render", dir_.PathOf("run.orcsrec"), "--out", dir_.PathOf("x.txt")}), {"--out", ".png"});
}

}  // namespace
}  // namespace orcs
