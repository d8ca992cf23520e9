#include "model/evaluation/recording_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>

#include "model/evaluation/recorder.h"
#include "model/scene/world_setup.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::evaluation {
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

std::string SmallRecording(int steps = 30) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  Recorder recorder(simulation, RecordingSource{});
  for (int i = 0; i < steps; ++i) {
    simulation.Step();
    recorder.Sample();
  }
  return recorder.Finish();
}

TEST(RecordingReaderTest, RefusesAForeignFile) {
  EXPECT_THAT(InputErrorOf([] { ParseRecording("PK\x03\x04 a zip file, not ours", "x.orcsrec"); }),
              HasSubstr("x.orcsrec: not an orcs recording"));
  EXPECT_THAT(InputErrorOf([] { ParseRecording("", "empty.orcsrec"); }), HasSubstr("not an orcs recording"));
}

TEST(RecordingReaderTest, RefusesANewerVersionAndSaysWhatToDo) {
  std::string bytes = SmallRecording(1);
  const std::uint32_t newer = kRecordingVersion + 1;
  std::memcpy(bytes.data() + 8, &newer, sizeof newer);
  EXPECT_THAT(InputErrorOf([&] { ParseRecording(bytes, "new.orcsrec"); }),
              HasSubstr("new.orcsrec: recording format version 2 is newer than this orcs reads (1): update orcs"));
}

TEST(RecordingReaderTest, RefusesATruncatedFileWhereverItIsCut) {
  const std::string bytes = SmallRecording();
  for (std::size_t keep : {std::size_t{10}, std::size_t{20}, bytes.size() / 2, bytes.size() - 1}) {
    const std::string message = InputErrorOf([&] { ParseRecording(bytes.substr(0, keep), "cut.orcsrec"); });
    EXPECT_THAT(message, HasSubstr("cut.orcsrec: ")) << keep;
    EXPECT_TRUE(message.find("truncated") != std::string::npos || message.find("not an orcs recording") !=
                std::string::npos) << keep << ": " << message;
  }
}

TEST(RecordingReaderTest, RefusesAHeaderThatIsNotTheFormats) {
  std::string bytes = SmallRecording(1);
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  bytes.replace(16, length, std::string(length, ' ').replace(0, 2, "[]"));
  EXPECT_THAT(InputErrorOf([&] { ParseRecording(bytes, "h.orcsrec"); }),
              HasSubstr("h.orcsrec: header: expected an object with 'channels' and 'bodies' arrays"));
}

TEST(RecordingReaderTest, BoundsTheDecompressedSize) {
  const std::string bytes = SmallRecording(100);
  RecordingLimits limits;
  limits.max_decompressed_bytes = 64 << 10;
  EXPECT_THAT(InputErrorOf([&] { ParseRecording(bytes, "big.orcsrec", limits); }),
              HasSubstr("big.orcsrec: frames exceed"));
}

TEST(RecordingReaderTest, ReadsOnlyRegularFiles) {
  test_support::TempDir dir;
  EXPECT_THAT(InputErrorOf([&] { ReadRecording(dir.path().string()); }), HasSubstr("not a regular file"));
  EXPECT_THAT(InputErrorOf([] { ReadRecording("/dev/zero"); }), HasSubstr("/dev/zero: not a regular file"));
  EXPECT_THAT(InputErrorOf([&] { ReadRecording(dir.PathOf("missing.orcsrec")); }), HasSubstr("no such file"));
  const std::string file = dir.Write("ok.orcsrec", SmallRecording(5));
  EXPECT_EQ(ReadRecording(file).frame_count(), 6);
}

}  // namespace
}  // namespace orcs::evaluation
