#include "hardware/dynamixel/protocol2.h"

#include <algorithm>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace orcs::dynamixel::protocol2 {
namespace {

constexpr std::uint16_t kPolynomial = 0x8005;
constexpr std::size_t kCrcSize = 2;
constexpr std::size_t kMaxLengthField = 0xFFFF;
constexpr std::uint8_t kStuffByte = 0xFD;

void AppendLe16(std::vector<std::uint8_t>& bytes, std::size_t value) {
  bytes.push_back(static_cast<std::uint8_t>(value & 0xFFu));
  bytes.push_back(static_cast<std::uint8_t>((value >> 8) & 0xFFu));
}

std::uint16_t ReadLe16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint16_t>(bytes[at] | (bytes[at + 1] << 8));
}

// Whether `bytes` ends with FF FF FD, the pattern after which an FD is stuffed.
bool EndsWithStuffPattern(const std::vector<std::uint8_t>& bytes) {
  const std::size_t n = bytes.size();
  return n >= 3 && bytes[n - 3] == 0xFF && bytes[n - 2] == 0xFF && bytes[n - 1] == kStuffByte;
}

// Header, id, length, the stuffed body (instruction on), CRC.
std::vector<std::uint8_t> Frame(std::uint8_t id, const std::vector<std::uint8_t>& body) {
  const std::vector<std::uint8_t> stuffed = Stuff(body);
  const std::size_t length = stuffed.size() + kCrcSize;
  if (length > kMaxLengthField) {
    throw std::length_error("Dynamixel 2.0 packet of length " + std::to_string(length) + " (at most " +
                            std::to_string(kMaxLengthField) + ")");
  }
  std::vector<std::uint8_t> packet(kHeader.begin(), kHeader.end());
  packet.push_back(id);
  AppendLe16(packet, length);
  packet.insert(packet.end(), stuffed.begin(), stuffed.end());
  AppendLe16(packet, Crc16(packet));
  return packet;
}

std::vector<std::uint8_t> AddressAndData(std::uint16_t address, std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> params;
  AppendLe16(params, address);
  params.insert(params.end(), data.begin(), data.end());
  return params;
}

}  // namespace

ErrorNumber ErrorNumberOf(std::uint8_t error) { return static_cast<ErrorNumber>(error & ~kAlertBit & 0xFFu); }

std::string ErrorText(std::uint8_t error) {
  static constexpr std::array<std::string_view, 8> kNumberNames{
      "", "result fail", "instruction", "CRC", "data range", "data length", "data limit", "access"};
  std::vector<std::string_view> names;
  std::string unknown;
  const auto number = static_cast<std::size_t>(ErrorNumberOf(error));
  if (number >= kNumberNames.size()) {
    unknown = "error number " + std::to_string(number);
    names.push_back(unknown);
  } else if (number != 0) {
    names.push_back(kNumberNames[number]);
  }
  if ((error & kAlertBit) != 0) names.push_back("hardware alert");
  return JoinErrorNames(names);
}

std::uint16_t Crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0;
  for (const std::uint8_t byte : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ (byte << 8));
    for (int bit = 0; bit < 8; ++bit) {
      const bool top = (crc & 0x8000u) != 0;
      crc = static_cast<std::uint16_t>(crc << 1);
      if (top) crc = static_cast<std::uint16_t>(crc ^ kPolynomial);
    }
  }
  return crc;
}

std::vector<std::uint8_t> Stuff(std::span<const std::uint8_t> bytes) {
  std::vector<std::uint8_t> stuffed;
  stuffed.reserve(bytes.size() + bytes.size() / 3);
  for (const std::uint8_t byte : bytes) {
    stuffed.push_back(byte);
    if (EndsWithStuffPattern(stuffed)) stuffed.push_back(kStuffByte);
  }
  return stuffed;
}

std::vector<std::uint8_t> Unstuff(std::span<const std::uint8_t> bytes) {
  std::vector<std::uint8_t> plain;
  plain.reserve(bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    plain.push_back(bytes[i]);
    if (EndsWithStuffPattern(plain) && i + 1 < bytes.size() && bytes[i + 1] == kStuffByte) ++i;
  }
  return plain;
}

std::vector<std::uint8_t> EncodeInstruction(std::uint8_t id, Instruction instruction,
                                            std::span<const std::uint8_t> params) {
  std::vector<std::uint8_t> body{static_cast<std::uint8_t>(instruction)};
  body.insert(body.end(), params.begin(), params.end());
  return Frame(id, body);
}

std::vector<std::uint8_t> EncodeStatus(std::uint8_t id, std::uint8_t error, std::span<const std::uint8_t> params) {
  std::vector<std::uint8_t> body{static_cast<std::uint8_t>(Instruction::kStatus), error};
  body.insert(body.end(), params.begin(), params.end());
  return Frame(id, body);
}

std::vector<std::uint8_t> EncodePing(std::uint8_t id) { return EncodeInstruction(id, Instruction::kPing, {}); }

std::vector<std::uint8_t> EncodeRead(std::uint8_t id, std::uint16_t address, std::uint16_t length) {
  std::vector<std::uint8_t> params;
  AppendLe16(params, address);
  AppendLe16(params, length);
  return EncodeInstruction(id, Instruction::kRead, params);
}

std::vector<std::uint8_t> EncodeWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data) {
  return EncodeInstruction(id, Instruction::kWrite, AddressAndData(address, data));
}

std::vector<std::uint8_t> EncodeRegWrite(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data) {
  return EncodeInstruction(id, Instruction::kRegWrite, AddressAndData(address, data));
}

std::vector<std::uint8_t> EncodeAction(std::uint8_t id) { return EncodeInstruction(id, Instruction::kAction, {}); }

std::vector<std::uint8_t> EncodeSyncRead(std::uint16_t address, std::uint16_t length,
                                         std::span<const std::uint8_t> ids) {
  std::vector<std::uint8_t> params;
  AppendLe16(params, address);
  AppendLe16(params, length);
  params.insert(params.end(), ids.begin(), ids.end());
  return EncodeInstruction(kBroadcastId, Instruction::kSyncRead, params);
}

std::vector<std::uint8_t> EncodeSyncWrite(std::uint16_t address, std::uint16_t data_length,
                                          std::span<const SyncWriteEntry> entries) {
  std::vector<std::uint8_t> params;
  AppendLe16(params, address);
  AppendLe16(params, data_length);
  for (const SyncWriteEntry& entry : entries) {
    if (entry.data.size() != data_length) {
      throw std::invalid_argument("Dynamixel 2.0 sync write: servo " + std::to_string(entry.id) + " has " +
                                  std::to_string(entry.data.size()) + " bytes, not " + std::to_string(data_length));
    }
    params.push_back(entry.id);
    params.insert(params.end(), entry.data.begin(), entry.data.end());
  }
  return EncodeInstruction(kBroadcastId, Instruction::kSyncWrite, params);
}

std::vector<std::uint8_t> EncodeBulkRead(std::span<const BulkReadEntry> entries) {
  std::vector<std::uint8_t> params;
  for (const BulkReadEntry& entry : entries) {
    params.push_back(entry.id);
    AppendLe16(params, entry.address);
    AppendLe16(params, entry.length);
  }
  return EncodeInstruction(kBroadcastId, Instruction::kBulkRead, params);
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
    const std::size_t available = std::min(kHeader.size(), buffer_.size() - pos);
    if (std::equal(kHeader.begin(), kHeader.begin() + static_cast<std::ptrdiff_t>(available),
                   buffer_.begin() + static_cast<std::ptrdiff_t>(pos))) {
      return available == kHeader.size();  // a partial header at the end: wait for the rest
    }
    ++pos;
    ++counts_.skipped_bytes;
  }
  return false;
}

void Parser::SkipHeader(std::size_t& pos, std::uint8_t id, std::size_t length, std::vector<DecodeEvent>& events) {
  ++counts_.length_errors;
  ++counts_.skipped_bytes;
  events.push_back(FailedDecode(DecodeOutcome::kBadLength, PacketKind::kInstruction, id, length));
  ++pos;
}

Parser::Step Parser::ParseAt(std::size_t& pos, std::vector<DecodeEvent>& events) {
  if (!SkipToHeader(pos) || buffer_.size() - pos < kPrefixSize) return Step::kWait;
  const std::uint8_t id = buffer_[pos + 4];
  const std::size_t length = ReadLe16(buffer_, pos + 5);
  if (length < 1 + kCrcSize || length > max_length_) {  // at least an instruction and the CRC
    SkipHeader(pos, id, length, events);
    return Step::kContinue;
  }
  const std::size_t total = kPrefixSize + length;
  if (buffer_.size() - pos < total) return Step::kWait;
  const auto framed = std::span(buffer_).subspan(pos, total);
  if (Crc16(framed.first(total - kCrcSize)) != ReadLe16(framed, total - kCrcSize)) {
    ++counts_.checksum_errors;
    events.push_back(FailedDecode(DecodeOutcome::kChecksumError, PacketKind::kInstruction, id, length));
  } else {
    Decode(pos, length, events);
  }
  pos += total;
  return Step::kContinue;
}

void Parser::Decode(std::size_t pos, std::size_t length, std::vector<DecodeEvent>& events) {
  const auto body = std::span(buffer_).subspan(pos + kPrefixSize, length - kCrcSize);
  std::vector<std::uint8_t> params = Unstuff(body);  // the instruction first (never part of FF FF FD)
  Packet packet;
  packet.id = buffer_[pos + 4];
  packet.instruction = params.front();
  params.erase(params.begin());
  if (packet.instruction == static_cast<std::uint8_t>(Instruction::kStatus)) {
    if (params.empty()) {  // a status packet without its error byte
      ++counts_.length_errors;
      events.push_back(FailedDecode(DecodeOutcome::kBadLength, PacketKind::kStatus, packet.id, length));
      return;
    }
    packet.kind = PacketKind::kStatus;
    packet.error = params.front();
    params.erase(params.begin());
  }
  packet.params = std::move(params);
  ++counts_.packets;
  events.push_back({DecodeOutcome::kPacket, std::move(packet), length});
}

}  // namespace orcs::dynamixel::protocol2
