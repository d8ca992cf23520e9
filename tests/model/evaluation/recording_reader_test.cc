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

// A run watched while it is written (orcs-robot --view): the recorder hands over its frames in flushed pieces, and
// a reader that allows an unfinished stream reads every frame flushed so far, wherever the file is cut.
TEST(RecordingReaderTest, ReadsARecordingStillBeingWrittenUpToItsLastCompleteFrame) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  Recorder recorder(simulation, RecordingSource{});
  std::string file;
  RecordingLimits live;
  live.allow_unfinished = true;
  for (int piece = 1; piece <= 3; ++piece) {
    for (int i = 0; i < 10; ++i) {
      simulation.Step();
      recorder.Sample();
    }
    file += recorder.TakeFlushed();
    const Recording so_far = ParseRecording(file, "live.orcsrec", live);
    EXPECT_FALSE(so_far.finished);
    EXPECT_EQ(so_far.frame_count(), 1 + 10 * piece) << "frame 0 and every frame flushed";
    EXPECT_THAT(InputErrorOf([&] { ParseRecording(file, "live.orcsrec"); }), HasSubstr("truncated"))
        << "a reader that does not allow it still refuses an unfinished stream";
  }
  // Cut anywhere after the header (a reader catching the file mid-write): never more frames than were flushed, the
  // values of those it reads as written.
  const Recording flushed = ParseRecording(file, "live.orcsrec", live);
  std::uint32_t header_length = 0;
  std::memcpy(&header_length, file.data() + 12, 4);
  for (std::size_t keep = 16 + header_length; keep < file.size(); keep += 7) {
    try {
      const Recording cut = ParseRecording(std::string_view(file).substr(0, keep), "cut.orcsrec", live);
      ASSERT_LE(cut.frame_count(), flushed.frame_count());
      EXPECT_EQ(std::vector<float>(flushed.values.begin(), flushed.values.begin() + static_cast<long>(cut.values.size())),
                cut.values) << keep;
    } catch (const InputError& error) {
      EXPECT_THAT(error.what(), HasSubstr("holds no frame")) << keep;  // cut before frame 0's bytes
    }
  }
  file += recorder.Finish();
  const Recording whole = ParseRecording(file, "live.orcsrec");
  EXPECT_TRUE(whole.finished);
  EXPECT_EQ(whole.frame_count(), 31);
  EXPECT_EQ(std::vector<float>(whole.values.begin(), whole.values.begin() + static_cast<long>(flushed.values.size())),
            flushed.values);
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
