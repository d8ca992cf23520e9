#include "model/control/keyframe_record.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::control {
namespace {

using test_support::InputErrorOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::StartsWith;

TEST(KeyframeRecordTest, ReadsRawRowsWithCommentsAndBlankLines) {
  const KeyframeRecord record = ParseKeyframeRecord(
      "# one motor\n# layout: raw\n\n0, 10, 0.5   # start\n250.5,-20,1\n", "r.csv", 1);
  EXPECT_EQ(record.layout, KeyframeLayout::kRaw);
  EXPECT_FALSE(record.layout_detected);
  ASSERT_EQ(record.frames.size(), 2u);
  EXPECT_EQ(record.frames[0].time_ms, 0.0);
  EXPECT_THAT(record.frames[0].inputs, ElementsAre(10.0, 0.5));
  EXPECT_EQ(record.frames[0].line, 4);
  EXPECT_EQ(record.frames[1].time_ms, 250.5);
  EXPECT_THAT(record.frames[1].inputs, ElementsAre(-20.0, 1.0));
}

TEST(KeyframeRecordTest, NormalisedLayoutBecomesRawInterleaved) {
  // Older layout: time, angle1, angle2, torque1, torque2 (normalised). Angle ±1 ↔ ±150°, torque n ↔ 2n − 1.
  const KeyframeRecord record = ParseKeyframeRecord("# layout: normalised\n0,0.5,-1,1,0.25\n", "r.csv", 2);
  EXPECT_EQ(record.layout, KeyframeLayout::kNormalised);
  EXPECT_THAT(record.frames[0].inputs, ElementsAre(75.0, 1.0, -150.0, -0.5));
}

TEST(KeyframeRecordTest, WithoutLayoutLineValuesWithinUnitRangeReadAsNormalised) {
  const KeyframeRecord old = ParseKeyframeRecord("0,0.5,-1,1,0.25\n", "r.csv", 2);
  EXPECT_TRUE(old.layout_detected);
  EXPECT_EQ(old.layout, KeyframeLayout::kNormalised);
  EXPECT_THAT(old.frames[0].inputs, ElementsAre(75.0, 1.0, -150.0, -0.5));

  const KeyframeRecord raw = ParseKeyframeRecord("0,0.5,-1,1,0.25\n10,30,0.5,-1,0.2\n", "r.csv", 2);
  EXPECT_TRUE(raw.layout_detected);
  EXPECT_EQ(raw.layout, KeyframeLayout::kRaw);  // 30° cannot be a normalised value
  EXPECT_THAT(raw.frames[0].inputs, ElementsAre(0.5, -1.0, 1.0, 0.25));
}

TEST(KeyframeRecordTest, RejectsWrongColumnCountNamingFileLineAndCounts) {
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("0,1,2\n10,1\n", "m.csv", 1); }),
            "m.csv:2: expected 3 columns (time in ms, then DesiredAngle and DesiredTorque of 1 motor), found 2");
}

TEST(KeyframeRecordTest, RejectsNonNumericAndNonFiniteFields) {
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("0,1,abc\n", "m.csv", 1); }),
            "m.csv:1: column 3 expected a finite number, found 'abc'");
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("# x\n0,nan,1\n", "m.csv", 1); }),
            "m.csv:2: column 2 expected a finite number, found 'nan'");
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("0,inf,1\n", "m.csv", 1); }),
            "m.csv:1: column 2 expected a finite number, found 'inf'");
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("0,,1\n", "m.csv", 1); }),
            "m.csv:1: column 2 expected a finite number, found ''");
}

TEST(KeyframeRecordTest, RejectsTimeGoingBackwardsAndNegativeTime) {
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("0,1,1\n20,1,1\n\n10,1,1\n", "m.csv", 1); }),
            "m.csv:4: time goes backwards: 10 ms after 20 ms on line 2");
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("-5,1,1\n", "m.csv", 1); }),
            "m.csv:1: column 1 expected a time ≥ 0 ms, found -5");
}

TEST(KeyframeRecordTest, EqualTimesAreAllowed) {
  EXPECT_EQ(ParseKeyframeRecord("0,1,1\n0,2,1\n", "m.csv", 1).frames.size(), 2u);
}

TEST(KeyframeRecordTest, RejectsUnknownLayoutAndEmptyRecord) {
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("# layout: degrees\n0,1,1\n", "m.csv", 1); }),
            "m.csv:1: '# layout:' expected 'raw' or 'normalised', found 'degrees'");
  EXPECT_EQ(InputErrorOf([] { ParseKeyframeRecord("# only comments\n\n", "m.csv", 1); }),
            "m.csv: expected at least one keyframe row, found none");
}

TEST(KeyframeRecordTest, CrlfLineEndingsAreAccepted) {
  const KeyframeRecord record = ParseKeyframeRecord("# layout: raw\r\n0,1,1\r\n10,2,1\r\n", "m.csv", 1);
  EXPECT_EQ(record.layout, KeyframeLayout::kRaw);
  EXPECT_THAT(record.frames[1].inputs, ElementsAre(2.0, 1.0));
}

TEST(KeyframeRecordTest, FormatRoundTripsExactly) {
  KeyframeRecord record;
  record.motor_count = 1;
  record.frames = {{0.0, {0.1 + 0.2, 1.0 / 3.0}, 0}, {12.5, {-150.0, -1.0}, 0}};
  const std::string text = FormatKeyframeRecord(record, {"sniffed from 127.0.0.1"});
  EXPECT_THAT(text, StartsWith("# sniffed from 127.0.0.1\n# layout: raw\n"));
  const KeyframeRecord back = ParseKeyframeRecord(text, "back.csv", 1);
  ASSERT_EQ(back.frames.size(), 2u);
  EXPECT_EQ(back.frames[0].inputs, record.frames[0].inputs);
  EXPECT_EQ(back.frames[1].time_ms, 12.5);
  EXPECT_EQ(back.frames[1].inputs, record.frames[1].inputs);
}

TEST(KeyframeRecordTest, UnreadableFileIsNamed) {
  test_support::TempDir dir;
  const std::string missing = dir.PathOf("missing.csv");
  EXPECT_EQ(InputErrorOf([&] { ReadKeyframeRecord(missing, 21); }), missing + ": cannot read the file: no such file");
  EXPECT_EQ(InputErrorOf([&] { ReadKeyframeRecord(dir.path().string(), 21); }),
            dir.path().string() + ": not a regular file (a directory)");
  EXPECT_EQ(InputErrorOf([&] { ReadKeyframeRecord("/dev/zero", 21); }), "/dev/zero: not a regular file (a character device)");
}

}  // namespace
}  // namespace orcs::control
