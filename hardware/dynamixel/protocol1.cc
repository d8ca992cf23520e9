#include "hardware/dynamixel/protocol1.h"

#include <array>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace orcs::dynamixel::protocol1 {
namespace {

constexpr std::uint8_t kHeaderByte = 0xFF;
// Length = parameter count + 2 (the instruction/error byte and the checksum).
constexpr std::size_t kLengthOverhead = 2;

// FF FF id length code params... checksum, where `code` is an instruction or an error byte.
std::vector<std::uint8_t> Frame(std::uint8_t id, std::uint8_t code, std::span<const std::uint8_t> params) {
  if (params.size() > kMaxParams) {
    throw std::length_error("Dynamixel 1.0 packet with " + std::to_string(params.size()) + " parameters (at most " +
                            std::to_string(kMaxParams) + ")");
  }
  std::vector<std::uint8_t> packet{kHeaderByte, kHeaderByte, id,
                                   static_cast<std::uint8_t>(params.size() + kLengthOverhead), code};
  packet.insert(packet.end(), params.begin(), params.end());
  packet.push_back(Checksum(std::span(packet).subspan(2)));
  return packet;
}

std::vector<std::uint8_t> AddressAndData(std::uint8_t address, std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> params{address};
  params.insert(params.end(), data.begin(), data.end());
  return params;
}

}  // namespace

std::uint8_t Checksum(std::span<const std::uint8_t> id_to_last_param) {
  unsigned sum = 0;
  for (const std::uint8_t byte : id_to_last_param) sum += byte;
  return static_cast<std::uint8_t>(~sum & 0xFFu);
}

std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> params) {
  return Frame(id, static_cast<std::uint8_t>(instruction), params);
}

std::vector<std::uint8_t> EncodeStatus(std::uint8_t id, std::uint8_t error, std::span<const std::uint8_t> params) {
  return Frame(id, error, params);
}

std::vector<std::uint8_t> EncodePing(std::uint8_t id) { return EncodeInstruction(id, Instruction::kPing, {}); }

std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint8_t address, std::uint8_t length) {
  const std::array<std::uint8_t, 2> params{address, length};
  return EncodeInstruction(id, Instruction::kRead, params);
}

std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint8_t address, std::span<const std::uint8_t> data) {
  return EncodeInstruction(id, Instruction::kWrite, AddressAndData(address, data));
}

std::vector<std::uint8_t> EncodeRegWrite(std::uint8_t id, std::uint8_t address, std::span<const std::uint8_t> data) {
  return EncodeInstruction(id, Instruction::kRegWrite, AddressAndData(address, data));
}

std::vector<std::uint8_t> EncodeAction(std::uint8_t id) { return EncodeInstruction(id, Instruction::kAction, {}); }

std::vector<std::uint8_t> EncodeSyncWrite(std::uint8_t address, std::uint8_t data_length,
                                          std::span<const SyncWriteEntry> entries) {
  std::vector<std::uint8_t> params{address, data_length};
  for (const SyncWriteEntry& entry : entries) {
    if (entry.data.size() != data_length) {
      throw std::invalid_argument("Dynamixel 1.0 sync write: servo " + std::to_string(entry.id) + " has " +
                                  std::to_string(entry.data.size()) + " bytes, not " + std::to_string(data_length));
    }
    params.push_back(entry.id);
    params.insert(params.end(), entry.data.begin(), entry.data.end());
  }
  return EncodeInstruction(kBroadcastId, Instruction::kSyncWrite, params);
}

std::vector<std::uint8_t> EncodeBulkRead(std::span<const BulkReadEntry> entries) {
  std::vector<std::uint8_t> params{0x00};  // the manual's leading 0x00
  for (const BulkReadEntry& entry : entries) {
    params.insert(params.end(), {entry.length, entry.id, entry.address});
  }
  return EncodeInstruction(kBroadcastId, Instruction::kBulkRead, params);
}

std::string ErrorText(std::uint8_t error) {
  struct Name {
    std::uint8_t bit;
    std::string_view text;
  };
  static constexpr std::array<Name, 8> kNames{{{0x80, "bit 7"},
                                               {kInstructionError, "instruction"},
                                               {kOverloadError, "overload"},
                                               {kChecksumError, "checksum"},
                                               {kRangeError, "range"},
                                               {kOverheatingError, "overheating"},
                                               {kAngleLimitError, "angle limit"},
                                               {kInputVoltageError, "input voltage"}}};
  std::vector<std::string_view> names;
  for (const Name& name : kNames) {
    if ((error & name.bit) != 0) names.push_back(name.text);
  }
  return JoinErrorNames(names);
}

std::vector<DecodeEvent> Parser::Feed(std::span<const std::uint8_t> bytes) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::vector<DecodeEvent> events;
  std::size_t pos = 0;
  while (ParseAt(pos, events) == Step::kContinue) {
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
  return events;
}

bool Parser::SkipToHeader(std::size_t& pos) {
  while (pos < buffer_.size()) {
    if (buffer_[pos] == kHeaderByte) {
      if (pos + 1 == buffer_.size()) return false;  // maybe the first half of a header: wait
      if (buffer_[pos + 1] == kHeaderByte) return true;
    }
    ++pos;
    ++counts_.skipped_bytes;
  }
  return false;
}

Parser::Step Parser::ParseAt(std::size_t& pos, std::vector<DecodeEvent>& events) {
  if (!SkipToHeader(pos) || buffer_.size() - pos < kHeaderSize) return Step::kWait;
  const std::uint8_t id = buffer_[pos + 2];
  const std::size_t length = buffer_[pos + 3];
  if (id == kHeaderByte) {  // FF FF FF: no id is 0xFF, so the header starts one byte later
    ++pos;
    ++counts_.skipped_bytes;
    return Step::kContinue;
  }
  if (length < kLengthOverhead) {
    ++counts_.length_errors;
    ++counts_.skipped_bytes;
    events.push_back(FailedDecode(DecodeOutcome::kBadLength, kind_, id, length));
    ++pos;
    return Step::kContinue;
  }
  const std::size_t total = kHeaderSize + length;
  if (buffer_.size() - pos < total) return Step::kWait;
  const auto checked = std::span(buffer_).subspan(pos + 2, total - 3);
  if (Checksum(checked) != buffer_[pos + total - 1]) {
    ++counts_.checksum_errors;
    events.push_back(FailedDecode(DecodeOutcome::kChecksumError, kind_, id, length));
  } else {
    ++counts_.packets;
    events.push_back(MakePacketEvent(pos, length));
  }
  pos += total;
  return Step::kContinue;
}

DecodeEvent Parser::MakePacketEvent(std::size_t pos, std::size_t length) const {
  Packet packet;
  packet.kind = kind_;
  packet.id = buffer_[pos + 2];
  const std::uint8_t code = buffer_[pos + 4];
  if (kind_ == PacketKind::kStatus) {
    packet.instruction = static_cast<std::uint8_t>(Instruction::kStatus);
    packet.error = code;
  } else {
    packet.instruction = code;
  }
  const auto first = buffer_.begin() + static_cast<std::ptrdiff_t>(pos + 5);
  packet.params.assign(first, first + static_cast<std::ptrdiff_t>(length - kLengthOverhead));
  return {DecodeOutcome::kPacket, std::move(packet), length};
}

}  // namespace orcs::dynamixel::protocol1
