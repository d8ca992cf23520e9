// Dynamixel Protocol 1.0: encoding instruction and status packets, and decoding either from a byte stream.
//
// A packet is FF FF, id, length (= parameter count + 2), instruction (status: error byte), parameters, checksum;
// the checksum is the low byte of the complement of the sum of id, length, instruction/error and parameters.
// The framing does not tell an instruction from a status packet, so a Parser is told which one it reads:
// the bus driver reads status packets, the servo-bus emulator reads instructions. Pure: no I/O, no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hardware/dynamixel/packet.h"

namespace orcs::dynamixel::protocol1 {

/// Bytes before the first parameter's framing: FF FF, id, length.
inline constexpr std::size_t kHeaderSize = 4;
/// The most parameters a packet can carry: the length byte counts them plus 2.
inline constexpr std::size_t kMaxParams = 253;

/// The status error byte's bits (several may be set at once).
enum ErrorBit : std::uint8_t {
  kInputVoltageError = 0x01,  ///< supply voltage outside the control table's range
  kAngleLimitError = 0x02,    ///< goal position outside the CW/CCW angle limits
  kOverheatingError = 0x04,   ///< internal temperature above the control table's limit
  kRangeError = 0x08,         ///< an instruction's value out of its range
  kChecksumError = 0x10,      ///< the servo received an instruction with a wrong checksum
  kOverloadError = 0x20,      ///< the load exceeds the torque the servo may use
  kInstructionError = 0x40,   ///< unknown instruction, or ACTION without REG_WRITE
};

/// The checksum of a packet's id, length, instruction/error and parameters: ~(their sum) & 0xFF.
std::uint8_t Checksum(std::span<const std::uint8_t> id_to_last_param);

/// Any instruction packet. Throws std::length_error for more than kMaxParams parameters.
std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> params);
/// A status packet (what a servo, or the emulator, answers). Throws std::length_error as above.
std::vector<std::uint8_t> EncodeStatus(std::uint8_t id, std::uint8_t error, std::span<const std::uint8_t> params);

/// PING of one servo.
std::vector<std::uint8_t> EncodePing(std::uint8_t id);
/// READ of `length` bytes from `address`.
std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint8_t address, std::uint8_t length);
/// WRITE of `data` at `address`.
std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint8_t address, std::span<const std::uint8_t> data);
/// REG_WRITE of `data` at `address`, applied by a later ACTION.
std::vector<std::uint8_t> EncodeRegWrite(std::uint8_t id, std::uint8_t address, std::span<const std::uint8_t> data);
/// ACTION: apply the held REG_WRITEs (usually to kBroadcastId).
std::vector<std::uint8_t> EncodeAction(std::uint8_t id);

/// SYNC_WRITE (broadcast) of `data_length` bytes at `address` to each entry's servo. Throws std::invalid_argument
/// when an entry's data is not data_length bytes, std::length_error when the packet would be too long.
std::vector<std::uint8_t> EncodeSyncWrite(std::uint8_t address, std::uint8_t data_length,
                                          std::span<const SyncWriteEntry> entries);

/// One servo's part of a BULK_READ.
struct BulkReadEntry {
  std::uint8_t id = 0;       ///< the servo
  std::uint8_t address = 0;  ///< first control-table byte to read
  std::uint8_t length = 0;   ///< how many bytes
};
/// BULK_READ (broadcast, MX series): each servo answers its own status packet, in the entries' order.
std::vector<std::uint8_t> EncodeBulkRead(std::span<const BulkReadEntry> entries);

/// The set error bits by name, highest bit first, e.g. "overload, overheating"; "no error" for 0.
std::string ErrorText(std::uint8_t error);

/// Decodes packets of one kind from a byte stream fed in arbitrary pieces. Skips garbage before a header,
/// waits for a whole packet, reports and counts packets with a wrong checksum (discarding them) and impossible
/// lengths (skipping the header). Holds at most one unfinished packet (≤ 259 bytes) between calls.
class Parser {
 public:
  /// `kind`: what the stream carries (status packets for a driver, instructions for an emulator).
  explicit Parser(PacketKind kind) : kind_(kind) {}

  /// Appends `bytes` to the stream; returns what they completed, in order.
  std::vector<DecodeEvent> Feed(std::span<const std::uint8_t> bytes);

  const DecodeCounts& counts() const { return counts_; }
  /// Bytes held for a packet not yet complete.
  std::size_t buffered() const { return buffer_.size(); }

 private:
  enum class Step { kWait, kContinue };
  Step ParseAt(std::size_t& pos, std::vector<DecodeEvent>& events);
  bool SkipToHeader(std::size_t& pos);
  DecodeEvent MakePacketEvent(std::size_t pos, std::size_t length) const;

  PacketKind kind_;
  std::vector<std::uint8_t> buffer_;
  DecodeCounts counts_;
};

}  // namespace orcs::dynamixel::protocol1
