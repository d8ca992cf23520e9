// What the two Dynamixel protocols share: instruction codes, the decoded packet and what a parser reports.
//
// Protocol 1.0 and 2.0 frame packets differently (header, length width, checksum vs CRC, byte stuffing), but once
// decoded a packet is the same thing: an id, an instruction (or, for a servo's answer, a status with an error
// byte) and parameters. protocol1.h and protocol2.h encode and decode them; nothing here does I/O.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::dynamixel {

/// The id every servo on the bus obeys; servos do not answer it (except PING in 2.0 and the sync/bulk reads).
inline constexpr std::uint8_t kBroadcastId = 0xFE;

/// Instruction codes, the same in both protocols where both have them.
enum class Instruction : std::uint8_t {
  kPing = 0x01,          ///< is a servo with this id there? (2.0: answers model number and firmware)
  kRead = 0x02,          ///< read bytes of the control table
  kWrite = 0x03,         ///< write bytes of the control table
  kRegWrite = 0x04,      ///< write, but hold it until ACTION
  kAction = 0x05,        ///< apply the held REG_WRITEs
  kFactoryReset = 0x06,  ///< restore the factory control table
  kReboot = 0x08,        ///< restart the servo
  kStatus = 0x55,        ///< 2.0: marks a status packet (a servo's answer); used for status packets of 1.0 too
  kSyncRead = 0x82,      ///< 2.0: read the same bytes of several servos
  kSyncWrite = 0x83,     ///< write the same bytes of several servos, each its own data
  kBulkRead = 0x92,      ///< read different bytes of several servos
};

/// Who sent a packet: the controller (an instruction) or a servo (a status packet, its answer).
enum class PacketKind : std::uint8_t {
  kInstruction,  ///< controller → servo
  kStatus,       ///< servo → controller
};

/// A decoded packet of either protocol, with the framing (header, length, checksum/CRC, stuffing) removed.
struct Packet {
  PacketKind kind = PacketKind::kInstruction;  ///< instruction or status packet
  std::uint8_t id = 0;                          ///< servo id (0..253 in 1.0, 0..252 in 2.0), kBroadcastId for all
  std::uint8_t instruction = 0;                 ///< Instruction code; kStatus for status packets (both protocols)
  std::uint8_t error = 0;                       ///< status packets: the error byte; 0 for instruction packets
  std::vector<std::uint8_t> params;             ///< parameters (unstuffed); for status, the bytes after the error

  bool operator==(const Packet&) const = default;
};

/// One servo's part of a SYNC_WRITE (both protocols).
struct SyncWriteEntry {
  std::uint8_t id = 0;             ///< the servo
  std::vector<std::uint8_t> data;  ///< its bytes, as many as the SYNC_WRITE's data length
};

/// What a parser found in the byte stream.
enum class DecodeOutcome : std::uint8_t {
  kPacket,         ///< a whole, intact packet
  kChecksumError,  ///< a whole packet whose checksum (1.0) or CRC (2.0) does not match: discarded
  kBadLength,      ///< a header whose length field no packet can have: the header is skipped
};

/// One finding of a parser's Feed(), in stream order.
struct DecodeEvent {
  DecodeOutcome outcome = DecodeOutcome::kPacket;  ///< what was found
  /// kPacket: the packet. Otherwise only packet.id (as received) and packet.kind (1.0: the parser's kind; 2.0:
  /// kInstruction, since the instruction byte is not trusted, but kStatus for a status packet without error byte).
  Packet packet;
  std::size_t length = 0;                          ///< the length field as received (bytes after it, framed)

  bool operator==(const DecodeEvent&) const = default;
};

/// Counters a parser keeps over its whole life.
struct DecodeCounts {
  std::size_t packets = 0;          ///< intact packets reported
  std::size_t checksum_errors = 0;  ///< packets discarded for a wrong checksum/CRC
  std::size_t length_errors = 0;    ///< headers skipped for an impossible length
  std::size_t skipped_bytes = 0;    ///< bytes dropped while looking for a header (garbage, bad headers)
};

/// The event of a packet not decoded (kChecksumError, kBadLength): only its kind, id and length field are known.
DecodeEvent FailedDecode(DecodeOutcome outcome, PacketKind kind, std::uint8_t id, std::size_t length);

/// "ping", "read", "sync write", ...; "instruction 0x42" for a code not in Instruction.
std::string InstructionName(std::uint8_t instruction);

/// Joins names with ", " ("overload, overheating"); "no error" when there are none.
std::string JoinErrorNames(const std::vector<std::string_view>& names);

}  // namespace orcs::dynamixel
