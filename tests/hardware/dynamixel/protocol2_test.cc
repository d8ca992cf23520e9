// Packets from the ROBOTIS Protocol 2.0 manual (emanual.robotis.com/docs/en/dxl/protocol2), checked byte for byte:
// their CRCs are the manual's, so Crc16 is checked against ROBOTIS, not against itself.
#include "hardware/dynamixel/protocol2.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace orcs::dynamixel::protocol2 {
namespace {

using Bytes = std::vector<std::uint8_t>;

const Bytes kPingOfId1{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E};
// Servo 1 answers the ping: model 1030 (XM430-W350), firmware 38.
const Bytes kPingStatus{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0x06, 0x04, 0x26, 0x65, 0x5D};
// Servo 1 answers a read of Present Position (4 bytes): 166.
const Bytes kReadStatus{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00, 0x8C, 0xC0};
// Servo 1 acknowledges a write.
const Bytes kWriteStatus{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, 0x00, 0xA1, 0x0C};

TEST(Protocol2Test, Crc16MatchesTheManualsPackets) {
  EXPECT_EQ(Crc16(std::span(kPingOfId1).first(8)), 0x4E19);
  EXPECT_EQ(Crc16(std::span(kPingStatus).first(12)), 0x5D65);
  EXPECT_EQ(Crc16(Bytes{}), 0x0000);
}

TEST(Protocol2Test, EncodesTheManualsInstructionPackets) {
  EXPECT_EQ(EncodePing(1), kPingOfId1);
  // Read Present Position (132, 4 bytes) of servo 1.
  EXPECT_EQ(EncodeRead(1, 132, 4), (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x02, 0x84, 0x00, 0x04, 0x00,
                                          0x1D, 0x15}));
  // Write Goal Position (116) = 512 to servo 1.
  EXPECT_EQ(EncodeWrite(1, 116, Bytes{0x00, 0x02, 0x00, 0x00}),
            (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x03, 0x74, 0x00, 0x00, 0x02, 0x00, 0x00, 0xCA, 0x89}));
}

TEST(Protocol2Test, EncodesTheManualsSyncReadAndSyncWrite) {
  const Bytes ids{1, 2};
  EXPECT_EQ(EncodeSyncRead(132, 4, ids), (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x09, 0x00, 0x82, 0x84, 0x00, 0x04,
                                                0x00, 0x01, 0x02, 0xCE, 0xFA}));
  // Goal Position 150 to servo 1 and 170 to servo 2.
  const std::vector<SyncWriteEntry> entries{{1, {0x96, 0x00, 0x00, 0x00}}, {2, {0xAA, 0x00, 0x00, 0x00}}};
  EXPECT_EQ(EncodeSyncWrite(116, 4, entries),
            (Bytes{0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x11, 0x00, 0x83, 0x74, 0x00, 0x04, 0x00, 0x01, 0x96, 0x00, 0x00,
                   0x00, 0x02, 0xAA, 0x00, 0x00, 0x00, 0x82, 0x87}));
  const std::vector<SyncWriteEntry> short_entry{{1, {0x96}}};
  EXPECT_THROW(EncodeSyncWrite(116, 4, short_entry), std::invalid_argument);
}

TEST(Protocol2Test, EncodesTheManualsStatusPackets) {
  EXPECT_EQ(EncodeStatus(1, 0, Bytes{0x06, 0x04, 0x26}), kPingStatus);
  EXPECT_EQ(EncodeStatus(1, 0, Bytes{0xA6, 0x00, 0x00, 0x00}), kReadStatus);
  EXPECT_EQ(EncodeStatus(1, 0, {}), kWriteStatus);
}

TEST(Protocol2Test, DecodesTheManualsStatusPackets) {
  Parser parser;
  Bytes stream = kPingStatus;
  stream.insert(stream.end(), kReadStatus.begin(), kReadStatus.end());
  stream.insert(stream.end(), kWriteStatus.begin(), kWriteStatus.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].packet, (Packet{.kind = PacketKind::kStatus, .id = 1, .instruction = 0x55, .error = 0,
                                      .params = {0x06, 0x04, 0x26}}));
  EXPECT_EQ(events[1].packet.params, (Bytes{0xA6, 0x00, 0x00, 0x00}));
  EXPECT_EQ(events[2].outcome, DecodeOutcome::kPacket);
  EXPECT_EQ(events[2].packet.kind, PacketKind::kStatus);
  EXPECT_TRUE(events[2].packet.params.empty());
  EXPECT_EQ(parser.counts().packets, 3u);
}

TEST(Protocol2Test, DecodesInstructionPacketsAndRoundTripsEveryEncoder) {
  Parser parser;
  const std::vector<SyncWriteEntry> sync{{3, {1, 2}}, {4, {3, 4}}};
  const std::vector<BulkReadEntry> bulk{{.id = 7, .address = 132, .length = 4}, {.id = 8, .address = 126, .length = 2}};
  const Bytes ids{3, 4};
  const std::vector<Bytes> packets{EncodePing(9),
                                   EncodeRead(9, 132, 4),
                                   EncodeWrite(9, 116, Bytes{1, 2}),
                                   EncodeRegWrite(9, 116, Bytes{1}),
                                   EncodeAction(kBroadcastId),
                                   EncodeSyncRead(132, 4, ids),
                                   EncodeSyncWrite(116, 2, sync),
                                   EncodeBulkRead(bulk)};
  const Bytes instructions{0x01, 0x02, 0x03, 0x04, 0x05, 0x82, 0x83, 0x92};
  for (std::size_t i = 0; i < packets.size(); ++i) {
    const auto events = parser.Feed(packets[i]);
    ASSERT_EQ(events.size(), 1u) << i;
    ASSERT_EQ(events[0].outcome, DecodeOutcome::kPacket) << i;
    const Packet& packet = events[0].packet;
    EXPECT_EQ(packet.kind, PacketKind::kInstruction) << i;
    EXPECT_EQ(packet.instruction, instructions[i]) << i;
    EXPECT_EQ(EncodeInstruction(packet.id, static_cast<Instruction>(packet.instruction), packet.params), packets[i])
        << i;
  }
  EXPECT_EQ(parser.counts().packets, packets.size());
}

TEST(Protocol2Test, EncodesBulkReadParametersAsIdAddressLength) {
  const std::vector<BulkReadEntry> bulk{{.id = 1, .address = 0x0084, .length = 4}};
  const Bytes packet = EncodeBulkRead(bulk);
  EXPECT_EQ(Bytes(packet.begin() + 7, packet.end() - 2), (Bytes{0x92, 0x01, 0x84, 0x00, 0x04, 0x00}));
}

TEST(Protocol2Test, StuffsFfFfFdAndUnstuffsItBack) {
  EXPECT_EQ(Stuff(Bytes{0xFF, 0xFF, 0xFD}), (Bytes{0xFF, 0xFF, 0xFD, 0xFD}));
  EXPECT_EQ(Stuff(Bytes{0xFF, 0xFF, 0xFD, 0xFD}), (Bytes{0xFF, 0xFF, 0xFD, 0xFD, 0xFD}));
  EXPECT_EQ(Stuff(Bytes{0xFF, 0xFF, 0xFF, 0xFD, 0x00}), (Bytes{0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x00}));
  EXPECT_EQ(Stuff(Bytes{0xFF, 0xFD, 0xFF}), (Bytes{0xFF, 0xFD, 0xFF}));
  const std::vector<Bytes> plains{{0xFF, 0xFF, 0xFD},
                                  {0xFF, 0xFF, 0xFD, 0xFD},
                                  {0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD},
                                  {0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x00},
                                  {0x01, 0xFD, 0xFF}};
  for (const Bytes& plain : plains) {
    EXPECT_EQ(Unstuff(Stuff(plain)), plain);
  }
}

TEST(Protocol2Test, ParametersHoldingAHeaderAreStuffedOnTheWireAndDecodedIntact) {
  const Bytes data{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0xFF, 0xFF, 0xFD};
  const Bytes packet = EncodeWrite(1, 0x00FF, data);  // address FF 00: one more FF on the wire, no pattern
  // Stuffed: 03 | FF 00 FF FF FD FD 00 01 FF FF FD FD: the length counts the two added FDs.
  EXPECT_EQ(packet[5] | (packet[6] << 8), 1 + 2 + 8 + 2 + 2);
  // The wire has no header after the packet's own.
  for (std::size_t i = 1; i + 3 < packet.size(); ++i) {
    EXPECT_FALSE(packet[i] == 0xFF && packet[i + 1] == 0xFF && packet[i + 2] == 0xFD && packet[i + 3] == 0x00) << i;
  }
  Parser parser;
  const auto events = parser.Feed(packet);
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].outcome, DecodeOutcome::kPacket);
  Bytes expected{0xFF, 0x00};
  expected.insert(expected.end(), data.begin(), data.end());
  EXPECT_EQ(events[0].packet.params, expected);
}

TEST(Protocol2Test, AFlippedByteIsACountedCrcErrorAndTheNextPacketStillDecodes) {
  for (std::size_t flipped = 7; flipped < kReadStatus.size(); ++flipped) {
    Parser parser;
    Bytes stream = kReadStatus;
    stream[flipped] ^= 0x10;
    stream.insert(stream.end(), kWriteStatus.begin(), kWriteStatus.end());
    const auto events = parser.Feed(stream);
    ASSERT_EQ(events.size(), 2u) << flipped;
    EXPECT_EQ(events[0].outcome, DecodeOutcome::kChecksumError) << flipped;
    EXPECT_EQ(events[1].outcome, DecodeOutcome::kPacket) << flipped;
    EXPECT_EQ(parser.counts().checksum_errors, 1u) << flipped;
    EXPECT_EQ(parser.counts().packets, 1u) << flipped;
  }
}

TEST(Protocol2Test, SkipsGarbageAndPartialHeadersBeforeAPacket) {
  Parser parser;
  Bytes stream{0x00, 0xFF, 0xFF, 0x12, 0xFF, 0xFF, 0xFD, 0x01, 0xFF};
  stream.insert(stream.end(), kPingOfId1.begin(), kPingOfId1.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].packet.instruction, 0x01);
  EXPECT_EQ(events[0].packet.id, 1);
  EXPECT_EQ(parser.counts().skipped_bytes, 9u);
}

TEST(Protocol2Test, APacketSplitAcrossFeedsIsReportedOnceWhole) {
  Parser parser;
  // Pieces cut inside the header, the length and the CRC.
  EXPECT_TRUE(parser.Feed(Bytes{0xAA, 0xFF, 0xFF}).empty());
  EXPECT_TRUE(parser.Feed(Bytes{0xFD, 0x00, 0x01, 0x08}).empty());
  EXPECT_TRUE(parser.Feed(Bytes{0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00, 0x8C}).empty());
  const auto events = parser.Feed(Bytes{0xC0});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].packet.params, (Bytes{0xA6, 0x00, 0x00, 0x00}));
  EXPECT_EQ(parser.buffered(), 0u);
  EXPECT_EQ(parser.counts().skipped_bytes, 1u);
}

TEST(Protocol2Test, AnAbsurdLengthIsRejectedWithoutWaitingForOrHoldingIt) {
  Parser parser;
  Bytes stream{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0xFF, 0xFF};  // length 65535
  stream.insert(stream.end(), kPingOfId1.begin(), kPingOfId1.end());
  const auto events = parser.Feed(stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kBadLength);
  EXPECT_EQ(events[0].length, 0xFFFFu);
  EXPECT_EQ(events[1].outcome, DecodeOutcome::kPacket);
  EXPECT_EQ(parser.counts().length_errors, 1u);
  EXPECT_EQ(parser.buffered(), 0u);
}

TEST(Protocol2Test, TheMaxLengthIsTheParsersChoiceAndTooShortLengthsAreRejected) {
  Parser small(/*max_length=*/6);
  EXPECT_EQ(small.Feed(kReadStatus)[0].outcome, DecodeOutcome::kBadLength);  // length 8
  EXPECT_EQ(small.Feed(kWriteStatus)[0].outcome, DecodeOutcome::kPacket);    // length 4

  Parser parser;
  const auto events = parser.Feed(Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x02, 0x00});  // no room for a CRC
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kBadLength);
  EXPECT_EQ(parser.buffered(), 0u);
}

TEST(Protocol2Test, AStatusPacketWithoutItsErrorByteIsABadLength) {
  Parser parser;
  Bytes packet{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x55};
  const std::uint16_t crc = Crc16(packet);
  packet.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  packet.push_back(static_cast<std::uint8_t>(crc >> 8));
  const auto events = parser.Feed(packet);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].outcome, DecodeOutcome::kBadLength);
  EXPECT_EQ(parser.counts().packets, 0u);
}

TEST(Protocol2Test, ErrorTextNamesTheErrorNumberAndTheAlert) {
  EXPECT_EQ(ErrorText(0x00), "no error");
  EXPECT_EQ(ErrorText(0x01), "result fail");
  EXPECT_EQ(ErrorText(0x02), "instruction");
  EXPECT_EQ(ErrorText(0x03), "CRC");
  EXPECT_EQ(ErrorText(0x04), "data range");
  EXPECT_EQ(ErrorText(0x05), "data length");
  EXPECT_EQ(ErrorText(0x06), "data limit");
  EXPECT_EQ(ErrorText(0x07), "access");
  EXPECT_EQ(ErrorText(0x80), "hardware alert");
  EXPECT_EQ(ErrorText(0x84), "data range, hardware alert");
  EXPECT_EQ(ErrorText(0x09), "error number 9");
  EXPECT_EQ(ErrorNumberOf(0x87), ErrorNumber::kAccessError);
}

}  // namespace
}  // namespace orcs::dynamixel::protocol2
