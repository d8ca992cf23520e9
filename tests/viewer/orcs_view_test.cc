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

// Width and height from a PNG's IHDR chunk (big-endian, bytes 16–23).
std::pair<int, int> PngSize(const std::string& png) {
  const auto u32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  return png.size() < 24 ? std::pair{0, 0} : std::pair{u32(16), u32(20)};
}

TEST_F(OrcsViewTest, RendersAStillAndAClipThroughHeadlessChromium) {
  const std::string web = ORCS_SOURCE_DIR "/viewer/web";
  const ProcessResult still = RunProcess({kView, "--web-dir", web, "--render", dir_.PathOf("run.orcsrec"), "--out",
                                          dir_.PathOf("still.png"), "--width", "320", "--height", "180"});
  ASSERT_EQ(still.exit_code, 0) << still.err;
  const std::string png = dir_.Read("still.png");
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(PngSize(png), std::pair(320, 180));
  const ProcessResult clip = RunProcess({kView, "--web-dir", web, "--render", dir_.PathOf("run.orcsrec"), "--out",
                                         dir_.PathOf("clip.gif"), "--fps", "10", "--width", "160", "--height", "90"});
  ASSERT_EQ(clip.exit_code, 0) << clip.err;
  EXPECT_THAT(clip.out, HasSubstr("(3 frames)")) << "0.2 s at 10 frames/s: t = 0, 0.1, 0.2";
  EXPECT_EQ(dir_.Read("clip.gif").substr(0, 6), "GIF89a");
}

TEST_F(OrcsViewTest, ABadOptionIsOneLine) {
  ExpectBadInput(View({"--live", dir_.PathOf("run.orcsrec")}), {"--live"});
  ExpectBadInput(View({}), {"give recordings"});
  ExpectBadInput(View({"--render", dir_.PathOf("run.orcsrec"), "--out", dir_.PathOf("x.txt")}), {"--out", ".png"});
}

}  // namespace
}  // namespace orcs
