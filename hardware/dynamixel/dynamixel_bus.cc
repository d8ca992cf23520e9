#include "hardware/dynamixel/dynamixel_bus.h"

#include <array>
#include <optional>

namespace orcs::dynamixel {
namespace {

constexpr std::size_t kReadChunk = 64;  // bytes asked of the port at once

std::variant<protocol1::Parser, protocol2::Parser> ParserFor(Protocol protocol) {
  if (protocol == Protocol::kV1) return protocol1::Parser(PacketKind::kStatus);
  return protocol2::Parser();
}

}  // namespace

std::vector<std::uint8_t> LittleEndian(std::int64_t value, std::size_t size) {
  std::vector<std::uint8_t> bytes(size);
  const auto bits = static_cast<std::uint64_t>(value);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFF);
  return bytes;
}

std::int64_t FromLittleEndian(std::span<const std::uint8_t> bytes) {
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) bits |= static_cast<std::uint64_t>(bytes[i]) << (8 * i);
  return static_cast<std::int64_t>(bits);
}

DynamixelBus::DynamixelBus(std::unique_ptr<hardware::SerialLink> link, BusOptions options)
    : link_(std::move(link)), options_(options), parser_(ParserFor(options.protocol)) {}

std::string DynamixelBus::ErrorTextOf(std::uint8_t error) const {
  return options_.protocol == Protocol::kV1 ? protocol1::ErrorText(error) : protocol2::ErrorText(error);
}

void DynamixelBus::Send(const std::vector<std::uint8_t>& packet) {
  try {
    link_->Write(packet);
  } catch (const std::runtime_error& e) {
    throw BusError(e.what());
  }
  ++counts_.instructions;
}

std::vector<DecodeEvent> DynamixelBus::Decode(std::span<const std::uint8_t> bytes) {
  return std::visit([&](auto& parser) { return parser.Feed(bytes); }, parser_);
}

std::optional<Packet> DynamixelBus::AwaitStatus(std::uint8_t id) {
  const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
  std::array<std::uint8_t, kReadChunk> chunk{};
  while (true) {
    for (auto it = pending_.begin(); it != pending_.end(); ++it) {
      if (it->id != id) continue;
      Packet packet = std::move(*it);
      pending_.erase(it);
      return packet;
    }
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      ++counts_.timeouts;
      return std::nullopt;
    }
    std::size_t n = 0;
    try {
      n = link_->Read(chunk, left);
    } catch (const std::runtime_error& e) {
      throw BusError(e.what());
    }
    for (const DecodeEvent& event : Decode(std::span(chunk.data(), n))) {
      if (event.outcome == DecodeOutcome::kChecksumError) {
        ++counts_.checksum_errors;
        link_->DropInput();  // the rest of a garbled answer must not pass for the next one
        return std::nullopt;
      }
      if (event.outcome != DecodeOutcome::kPacket || event.packet.kind != PacketKind::kStatus) continue;
      ++counts_.replies;
      pending_.push_back(event.packet);
    }
  }
}

Packet DynamixelBus::Exchange(const std::vector<std::uint8_t>& packet, std::uint8_t id, int retries) {
  for (int attempt = 0; attempt <= retries; ++attempt) {
    if (attempt > 0) ++counts_.retries;
    pending_.clear();
    Send(packet);
    std::optional<Packet> status = AwaitStatus(id);
    if (!status) continue;
    if (status->error != 0) {
      ++counts_.alarms;
      throw ServoAlarm(id, status->error, ErrorTextOf(status->error));
    }
    return *status;
  }
  throw BusError(link_->path() + ": servo " + std::to_string(id) + " gave no intact answer within " +
                 std::to_string(options_.timeout.count() / 1000) + " ms in " + std::to_string(retries + 1) +
                 " tries (check its id, the baud rate and the cable)");
}

bool DynamixelBus::Ping(std::uint8_t id) {
  const auto packet = options_.protocol == Protocol::kV1 ? protocol1::EncodePing(id) : protocol2::EncodePing(id);
  try {
    Exchange(packet, id, options_.retries);
    return true;
  } catch (const ServoAlarm&) {
    return true;
  } catch (const BusError&) {
    return false;
  }
}

std::vector<std::uint8_t> DynamixelBus::Discover(std::uint8_t first, std::uint8_t last) {
  std::vector<std::uint8_t> found;
  for (int id = first; id <= last; ++id) {
    const auto servo = static_cast<std::uint8_t>(id);
    const auto packet =
        options_.protocol == Protocol::kV1 ? protocol1::EncodePing(servo) : protocol2::EncodePing(servo);
    try {
      Exchange(packet, servo, 0);
      found.push_back(servo);
    } catch (const ServoAlarm&) {
      found.push_back(servo);
    } catch (const BusError&) {
    }
  }
  return found;
}

std::vector<std::uint8_t> DynamixelBus::Read(std::uint8_t id, std::uint16_t address, std::uint16_t length) {
  const auto packet = options_.protocol == Protocol::kV1
                          ? protocol1::EncodeRead(id, static_cast<std::uint8_t>(address),
                                                  static_cast<std::uint8_t>(length))
                          : protocol2::EncodeRead(id, address, length);
  Packet status = Exchange(packet, id, options_.retries);
  if (status.params.size() != length) {
    throw BusError(link_->path() + ": servo " + std::to_string(id) + " answered a read of " + std::to_string(length) +
                   " bytes with " + std::to_string(status.params.size()));
  }
  return status.params;
}

void DynamixelBus::Write(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data) {
  const auto packet = options_.protocol == Protocol::kV1
                          ? protocol1::EncodeWrite(id, static_cast<std::uint8_t>(address), data)
                          : protocol2::EncodeWrite(id, address, data);
  Exchange(packet, id, options_.retries);
}

void DynamixelBus::SyncWrite(std::uint16_t address, std::uint16_t length, std::span<const SyncWriteEntry> entries) {
  Send(options_.protocol == Protocol::kV1
           ? protocol1::EncodeSyncWrite(static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(length), entries)
           : protocol2::EncodeSyncWrite(address, length, entries));
}

std::vector<std::vector<std::uint8_t>> DynamixelBus::SyncRead(std::span<const std::uint8_t> ids,
                                                              std::uint16_t address, std::uint16_t length) {
  std::vector<std::vector<std::uint8_t>> values;
  if (options_.protocol == Protocol::kV1) {
    for (std::uint8_t id : ids) values.push_back(Read(id, address, length));
    return values;
  }
  const auto packet = protocol2::EncodeSyncRead(address, length, ids);
  for (int attempt = 0; attempt <= options_.retries; ++attempt) {
    if (attempt > 0) ++counts_.retries;
    pending_.clear();
    Send(packet);
    values.clear();
    for (std::uint8_t id : ids) {
      std::optional<Packet> status = AwaitStatus(id);
      if (!status) break;
      if (status->error != 0) {
        ++counts_.alarms;
        throw ServoAlarm(id, status->error, ErrorTextOf(status->error));
      }
      if (status->params.size() != length) break;
      values.push_back(std::move(status->params));
    }
    if (values.size() == ids.size()) return values;
  }
  throw BusError(link_->path() + ": a sync read of " + std::to_string(ids.size()) +
                 " servos gave no intact answers in " + std::to_string(options_.retries + 1) + " tries");
}

}  // namespace orcs::dynamixel
