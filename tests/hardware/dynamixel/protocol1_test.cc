// Packets from the ROBOTIS Protocol 1.0 manual (emanual.robotis.com/docs/en/dxl/protocol1) and the DX-series
// manual's examples, checked byte for byte.
#include "hardware/dynamixel/protocol1.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace orcs::dynamixel::protocol1 {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<DecodeEvent> FeedAll(Parser& parser, const Bytes& bytes) { return parser.Feed(bytes); }

TEST(Protocol1Test, ChecksumIsTheComplementOfTheSumsLowByte) {
  EXPECT_EQ(Checksum(Bytes{0x01, 0x02, 0x01}), 0xFB);
  EXPECT_EQ(Checksum(Bytes{0xFE, 0x04, 0x03, 0x03, 0x01}), 0xF6);  // sum 0x109: only the low byte counts
}

TEST(Protocol1Test, EncodesTheManualsInstructionPackets) {
  EXPECT_EQ(EncodePing(1), (Bytes{0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB}));
  // Read the internal temperature (address 0x2B, 1 byte) of servo 1.
  EXPECT_EQ(EncodeRead(1, 0x2B, 1), (Bytes{0xFF, 0xFF, 0x01, 0x04, 0x02, 0x2B, 0x01, 0xCC}));
  // Set the id (address 3) of every servo to 1.
  EXPECT_EQ(EncodeWrite(kBroadcastId, 0x03, Bytes{0x01}), (Bytes{0xFF, 0xFF, 0xFE, 0x04, 0x03, 0x03, 0x01, 0xF6}));
  // Set the minimum punch (0x30) of servo 0 to 0x0040.
  EXPECT_EQ(EncodeWrite(0, 0x30, Bytes{0x40, 0x00}), (Bytes{0xFF, 0xFF, 0x00, 0x05, 0x03, 0x30, 0x40, 0x00, 0x87}));
}

TEST(Protocol1Test, EncodesTheManualsSyncWrite) {
  // Goal position and speed (0x1E, 4 bytes) of servos 0..3.
  const std::vector<SyncWriteEntry> entries{{0, {0x10, 0x00, 0x50, 0x01}},
                                            {1, {0x20, 0x02, 0x60, 0x03}},
                                            {2, {0x30, 0x00, 0x70, 0x01}},
                                            {3, {0x20, 0x02, 0x80, 0x03}}};
  EXPECT_EQ(EncodeSyncWrite(0x1E, 4, entries),
            (Bytes{0xFF, 0xFF, 0xFE, 0x18, 0x83, 0x1E, 0x04, 0x00, 0x10, 0x00, 0x50, 0x01, 0x01, 0x20, 0x02,
                   0x60, 0x03, 0x02, 0x30, 0x00, 0x70, 0x01, 0x03, 0x20, 0x02, 0x80, 0x03, 0x12}));
}

TEST(Protocol1Test, SyncWriteRefusesAnEntryOfTheWrongSize) {
  const std::vector<SyncWriteEntry> entries{{0, {0x10, 0x00}}};
  EXPECT_THROW(EncodeSyncWrite(0x1E, 4, entries), std::invalid_argument);
}

TEST(Protocol1Test, EncodesTheManualsBulkRead) {
  // 2 bytes at 0x1E of servo 1, 2 bytes at 0x24 of servo 2.
  const std::vector<BulkReadEntry> entries{{.id = 1, .address = 0x1E, .length = 2},
                                           {.id = 2, .address = 0x24, .length = 2}};
  EXPECT_EQ(EncodeBulkRead(entries),
            (Bytes{0xFF, 0xFF, 0xFE, 0x09, 0x92, 0x00, 0x02, 0x01, 0x1E, 0x02, 0x02, 0x24, 0x1D}));
}

TEST(Protocol1Test, EncodesRegWriteActionAndStatus) {
  EXPECT_EQ(EncodeRegWrite(1, 0x1E, Bytes{0x00, 0x02}), (Bytes{0xFF, 0xFF, 0x01, 0x05, 0x04, 0x1E, 0x00, 0x02, 0xD5}));
  EXPECT_EQ(EncodeAction(kBroadcastId), (Bytes{0xFF, 0xFF, 0xFE, 0x02, 0x05, 0xFA}));
  EXPECT_EQ(EncodeStatus(1, 0x00, Bytes{0x20}), (Bytes{0xFF, 0xFF, 0x01, 0x03, 0x00, 0x20, 0xDB}));
}

TEST(Protocol1Test, RefusesMoreParametersThanTheLengthByteHolds) {
  EXPECT_NO_THROW(EncodeWrite(1, 0, Bytes(kMaxParams - 1, 0)));
  EXPECT_THROW(EncodeWrite(1, 0, Bytes(kMaxParams, 0)), std::length_error);
}

TEST(Protocol1Test, DecodesTheManualsStatusPackets) {
  Parser parser(PacketKind::kStatus);
  // Servo 1 answers the temperature read: 32 °C; then servo 0 reports a range error.
  const auto events = FeedAll(parser, {0xFF, 0xFF, 0x01, 0x03, 0x00, 0x20, 0xDB, 0xFF, 0xFF, 0x00, 0x02, 0x08, 0xF5});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kPacket);
  EXPECT_EQ(events[0].packet, (Packet{.kind = PacketKind::kStatus, .id = 1, .instruction = 0x55, .error = 0,
                                      .params = {0x20}}));
  EXPECT_EQ(events[1].packet.id, 0);
  EXPECT_EQ(events[1].packet.error, kRangeError);
  EXPECT_TRUE(events[1].packet.params.empty());
  EXPECT_EQ(parser.counts().packets, 2u);
  EXPECT_EQ(parser.buffered(), 0u);
}

TEST(Protocol1Test, DecodesInstructionPacketsForTheEmulator) {
  Parser parser(PacketKind::kInstruction);
  const auto events = parser.Feed(EncodeWrite(0, 0x30, Bytes{0x40, 0x00}));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].packet, (Packet{.kind = PacketKind::kInstruction, .id = 0, .instruction = 0x03, .error = 0,
                                      .params = {0x30, 0x40, 0x00}}));
}

TEST(Protocol1Test, RoundTripsEveryEncoder) {
  Parser parser(PacketKind::kInstruction);
  const std::vector<SyncWriteEntry> sync{{3, {1, 2}}, {4, {0xFF, 0xFF}}};
  const std::vector<BulkReadEntry> bulk{{.id = 7, .address = 36, .length = 2}};
  const std::vector<Bytes> packets{EncodePing(9),
                                   EncodeRead(9, 36, 2),
                                   EncodeWrite(9, 30, Bytes{0xFF, 0xFF}),
                                   EncodeRegWrite(9, 30, Bytes{1}),
                                   EncodeAction(9),
                                   EncodeSyncWrite(30, 2, sync),
                                   EncodeBulkRead(bulk)};
  const std::vector<std::uint8_t> instructions{0x01, 0x02, 0x03, 0x04, 0x05, 0x83, 0x92};
  for (std::size_t i = 0; i < packets.size(); ++i) {
    const auto events = parser.Feed(packets[i]);
    ASSERT_EQ(events.size(), 1u) << i;
    ASSERT_EQ(events[0].outcome, DecodeOutcome::kPacket) << i;
    EXPECT_EQ(events[0].packet.instruction, instructions[i]) << i;
    // Re-encoding what was decoded gives the same bytes back.
    EXPECT_EQ(EncodeInstruction(events[0].packet.id, static_cast<Instruction>(events[0].packet.instruction),
                                events[0].packet.params),
              packets[i])
        << i;
  }
}

TEST(Protocol1Test, AFlippedByteIsACountedChecksumErrorAndTheNextPacketStillDecodes) {
  Parser parser(PacketKind::kStatus);
  Bytes bad = EncodeStatus(1, 0, Bytes{0x20, 0x01});
  bad[5] ^= 0x04;
  Bytes stream = bad;
  const Bytes good = EncodeStatus(2, 0, Bytes{0x33});
  stream.insert(stream.end(), good.begin(), good.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kChecksumError);
  EXPECT_EQ(events[0].packet.id, 1);
  EXPECT_EQ(events[1].outcome, DecodeOutcome::kPacket);
  EXPECT_EQ(events[1].packet.params, Bytes{0x33});
  EXPECT_EQ(parser.counts().checksum_errors, 1u);
  EXPECT_EQ(parser.counts().packets, 1u);
}

TEST(Protocol1Test, SkipsGarbageBeforeAHeaderIncludingALoneFF) {
  Parser parser(PacketKind::kStatus);
  Bytes stream{0x00, 0x12, 0xFF, 0x34, 0xFF};  // a lone FF, then one more FF before the real header: FF FF FF
  const Bytes good = EncodeStatus(5, 0, Bytes{0xAB});
  stream.insert(stream.end(), good.begin(), good.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].packet.id, 5);
  EXPECT_EQ(events[0].packet.params, Bytes{0xAB});
  EXPECT_EQ(parser.counts().skipped_bytes, 5u);
}

TEST(Protocol1Test, APacketSplitAcrossFeedsIsReportedOnceWhole) {
  Parser parser(PacketKind::kStatus);
  const Bytes packet = EncodeStatus(1, kOverloadError, Bytes{0x10, 0x20, 0x30});
  for (std::size_t i = 0; i + 1 < packet.size(); ++i) {
    EXPECT_TRUE(parser.Feed(Bytes{packet[i]}).empty()) << "byte " << i;
  }
  EXPECT_EQ(parser.buffered(), packet.size() - 1);
  const auto events = parser.Feed(Bytes{packet.back()});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].packet.error, kOverloadError);
  EXPECT_EQ(events[0].packet.params, (Bytes{0x10, 0x20, 0x30}));
  EXPECT_EQ(parser.buffered(), 0u);
}

TEST(Protocol1Test, ALengthBelowTwoIsRejectedAndTheFollowingPacketFound) {
  Parser parser(PacketKind::kStatus);
  Bytes stream{0xFF, 0xFF, 0x01, 0x01};
  const Bytes good = EncodeStatus(3, 0, {});
  stream.insert(stream.end(), good.begin(), good.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kBadLength);
  EXPECT_EQ(events[0].length, 1u);
  EXPECT_EQ(events[1].outcome, DecodeOutcome::kPacket);
  EXPECT_EQ(events[1].packet.id, 3);
  EXPECT_EQ(parser.counts().length_errors, 1u);
}

TEST(Protocol1Test, ErrorTextNamesEverySetBitHighestFirst) {
  EXPECT_EQ(ErrorText(0), "no error");
  EXPECT_EQ(ErrorText(kOverloadError | kOverheatingError), "overload, overheating");
  EXPECT_EQ(ErrorText(kInputVoltageError), "input voltage");
  EXPECT_EQ(ErrorText(kAngleLimitError), "angle limit");
  EXPECT_EQ(ErrorText(kRangeError), "range");
  EXPECT_EQ(ErrorText(kChecksumError), "checksum");
  EXPECT_EQ(ErrorText(kInstructionError), "instruction");
  EXPECT_EQ(ErrorText(0x7F), "instruction, overload, checksum, range, overheating, angle limit, input voltage");
}

}  // namespace
}  // namespace orcs::dynamixel::protocol1
