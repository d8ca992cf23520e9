// Dynamixel Protocol 2.0: encoding instruction and status packets, and decoding both from a byte stream.
//
// A packet is FF FF FD 00, id, length (2 bytes, little-endian: the bytes after it, CRC included), instruction,
// parameters, CRC (2 bytes, little-endian). A status packet's instruction is 0x55, followed by the error byte.
// Wherever FF FF FD appears from the instruction on, an FD is inserted after it (byte stuffing), so that no header
// appears inside a packet; the length counts the stuffed bytes. The CRC is ROBOTIS's CRC-16 (polynomial 0x8005,
// initial value 0, not reflected) over everything before it, as sent. Pure: no I/O, no clock.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hardware/dynamixel/packet.h"

namespace orcs::dynamixel::protocol2 {

/// FF FF FD 00: the header, of which the 00 is reserved.
inline constexpr std::array<std::uint8_t, 4> kHeader{0xFF, 0xFF, 0xFD, 0x00};
/// Bytes up to and including the length field: header, id, length (2).
inline constexpr std::size_t kPrefixSize = 7;
/// The largest length field a Parser accepts unless told otherwise; no servo answers more.
inline constexpr std::size_t kDefaultMaxLength = 1024;

/// The status error byte: bit 7 is the alert (a hardware error is in the control table's Hardware Error Status),
/// bits 0..6 an error number.
inline constexpr std::uint8_t kAlertBit = 0x80;
/// The status error byte's error numbers (error & 0x7F).
enum class ErrorNumber : std::uint8_t {
  kNone = 0,              ///< no error
  kResultFail = 1,        ///< the instruction could not be processed
  kInstructionError = 2,  ///< undefined instruction, or ACTION without REG_WRITE
  kCrcError = 3,          ///< the servo received a packet with a wrong CRC
  kDataRangeError = 4,    ///< data to write out of the range of its address
  kDataLengthError = 5,   ///< data shorter than the address's size
  kDataLimitError = 6,    ///< data beyond the limits set in the control table
  kAccessError = 7,       ///< write to a read-only address, read of a write-only one, or EEPROM with torque on
};

/// The error number of a status error byte (the alert bit masked off).
ErrorNumber ErrorNumberOf(std::uint8_t error);
/// The alert and the error number by name, e.g. "data range, hardware alert"; "no error" for 0.
std::string ErrorText(std::uint8_t error);

/// ROBOTIS's CRC-16 of `bytes` (polynomial 0x8005, initial value 0, no reflection, no final XOR).
std::uint16_t Crc16(std::span<const std::uint8_t> bytes);
/// Inserts an FD after each FF FF FD.
std::vector<std::uint8_t> Stuff(std::span<const std::uint8_t> bytes);
/// Removes the FD inserted after each FF FF FD; the inverse of Stuff.
std::vector<std::uint8_t> Unstuff(std::span<const std::uint8_t> bytes);

/// Any instruction packet. Throws std::length_error when the stuffed packet does not fit the length field.
std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> params);
/// A status packet (what a servo, or the emulator, answers). Throws std::length_error as above.
std::vector<std::uint8_t> EncodeStatus(std::uint8_t id, std::uint8_t error, std::span<const std::uint8_t> params);

/// PING of one servo, or of all with kBroadcastId (each answers in turn).
std::vector<std::uint8_t> EncodePing(std::uint8_t id);
/// READ of `length` bytes from `address`.
std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint16_t address, std::uint16_t length);
/// WRITE of `data` at `address`.
std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data);
/// REG_WRITE of `data` at `address`, applied by a later ACTION.
std::vector<std::uint8_t> EncodeRegWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data);
/// ACTION: apply the held REG_WRITEs (usually to kBroadcastId).
std::vector<std::uint8_t> EncodeAction(std::uint8_t id);
/// SYNC_READ (broadcast) of `length` bytes at `address` from each of `ids`; they answer in that order.
std::vector<std::uint8_t> EncodeSyncRead(std::uint16_t address, std::uint16_t length,
                                         std::span<const std::uint8_t> ids);
/// SYNC_WRITE (broadcast) of `data_length` bytes at `address` to each entry's servo. Throws std::invalid_argument
/// when an entry's data is not data_length bytes.
std::vector<std::uint8_t> EncodeSyncWrite(std::uint16_t address, std::uint16_t data_length,
                                          std::span<const SyncWriteEntry> entries);

/// One servo's part of a BULK_READ.
struct BulkReadEntry {
  std::uint8_t id = 0;        ///< the servo
  std::uint16_t address = 0;  ///< first control-table byte to read
  std::uint16_t length = 0;   ///< how many bytes
};
/// BULK_READ (broadcast): each servo answers its own status packet, in the entries' order.
std::vector<std::uint8_t> EncodeBulkRead(std::span<const BulkReadEntry> entries);

/// Decodes instruction and status packets (told apart by the 0x55 instruction) from a byte stream fed in arbitrary
/// pieces. Skips garbage before a header, waits for a whole packet, reports and counts packets with a wrong CRC
/// (discarding them) and lengths no packet can have or above `max_length` (skipping the header, never allocating
/// them); unstuffs the parameters. Holds at most one unfinished packet (≤ 7 + max_length bytes) between calls.
class Parser {
 public:
  explicit Parser(std::size_t max_length = kDefaultMaxLength) : max_length_(max_length) {}

  /// Appends `bytes` to the stream; returns what they completed, in order.
  std::vector<DecodeEvent> Feed(std::span<const std::uint8_t> bytes);

  const DecodeCounts& counts() const { return counts_; }
  /// Bytes held for a packet not yet complete.
  std::size_t buffered() const { return buffer_.size(); }

 private:
  enum class Step { kWait, kContinue };
  Step ParseAt(std::size_t& pos, std::vector<DecodeEvent>& events);
  bool SkipToHeader(std::size_t& pos);
  void SkipHeader(std::size_t& pos, std::uint8_t id, std::size_t length, std::vector<DecodeEvent>& events);
  void Decode(std::size_t pos, std::size_t length, std::vector<DecodeEvent>& events);

  std::size_t max_length_;
  std::vector<std::uint8_t> buffer_;
  DecodeCounts counts_;
};

}  // namespace orcs::dynamixel::protocol2
