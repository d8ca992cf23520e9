// The OSP/ODCP encoding: little-endian ints, floats as bit patterns, NUL strings, and every way a datagram can
// be malformed.
#include "worker/osp/osp_datagram.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace orcs::osp {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(OspDatagramTest, WritesLittleEndianIntsFloatBitsAndNulStringsThenTheEndByte) {
  const Bytes bytes = DatagramWriter().Byte(6).Int(0x01020304).Float(1.0f).String("ab").Finish();
  EXPECT_EQ(bytes, (Bytes{6, 4, 3, 2, 1, 0x00, 0x00, 0x80, 0x3f, 'a', 'b', 0, kDatagramEnd}));
  EXPECT_EQ(DatagramWriter().Int(-1).Finish(false), (Bytes{0xff, 0xff, 0xff, 0xff}));
}

TEST(OspDatagramTest, ReadsWhatWasWritten) {
  const Bytes bytes = DatagramWriter().Byte(43).Int(-7).Float(-2.5f).String("/Sim/X").String("").Finish();
  DatagramReader reader(bytes);
  EXPECT_EQ(reader.Byte(), 43);
  EXPECT_EQ(reader.Int(), -7);
  EXPECT_EQ(reader.Float(), -2.5f);
  EXPECT_EQ(reader.String(), "/Sim/X");
  EXPECT_EQ(reader.String(), "");
  EXPECT_TRUE(reader.AtEnd());  // only the end byte is left
}

TEST(OspDatagramTest, FloatsKeepTheirBitsNaNIncluded) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Bytes bytes = DatagramWriter().Float(nan).Float(-0.0f).Finish(false);
  DatagramReader reader(bytes);
  EXPECT_TRUE(std::isnan(reader.Float()));
  const float zero = reader.Float();
  EXPECT_TRUE(zero == 0.0f && std::signbit(zero));
}

TEST(OspDatagramTest, ShortDatagramsAreMalformedNotReadPastTheEnd) {
  const Bytes three = {1, 2, 3};
  DatagramReader reader(three);
  EXPECT_THROW(reader.Int(), MalformedDatagram);
  const Bytes empty;
  DatagramReader none(empty);
  EXPECT_THROW(none.Byte(), MalformedDatagram);
  EXPECT_TRUE(none.AtEnd());
}

TEST(OspDatagramTest, AStringWithoutNulIsMalformed) {
  const Bytes bytes = {'a', 'b', 'c'};
  DatagramReader reader(bytes);
  EXPECT_THROW(reader.String(), MalformedDatagram);
}

TEST(OspDatagramTest, ACountMustFitTheBytesLeft) {
  const Bytes fits = DatagramWriter().Int(2).Int(5).Int(6).Finish(false);
  DatagramReader good(fits);
  EXPECT_EQ(good.Count(4), 2);
  const Bytes too_many = DatagramWriter().Int(3).Int(5).Int(6).Finish(false);
  DatagramReader bad(too_many);
  EXPECT_THROW(bad.Count(4), MalformedDatagram);
  const Bytes negative = DatagramWriter().Int(-1).Finish(false);
  DatagramReader minus(negative);
  EXPECT_THROW(minus.Count(4), MalformedDatagram);
  const Bytes huge = DatagramWriter().Int(0x7fffffff).Finish(false);
  DatagramReader overflow(huge);
  EXPECT_THROW(overflow.Count(4), MalformedDatagram);
}

TEST(OspDatagramTest, AReplyBeyond1024BytesIsRefused) {
  DatagramWriter writer;
  writer.String(std::string(1022, 'x'));  // 1023 bytes + end byte = 1024: allowed
  EXPECT_EQ(writer.Finish().size(), kMaxDatagramBytes);
  writer.Byte(0);
  EXPECT_THROW(writer.Finish(), MalformedDatagram);
}

}  // namespace
}  // namespace orcs::osp
