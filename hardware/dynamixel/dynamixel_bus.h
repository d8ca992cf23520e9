// The Dynamixel bus driver: instructions out, status packets back, over a SerialLink (a real port or the
// emulator's pseudo-terminal), in Protocol 1.0 or 2.0.
//
// Every exchange waits for its answer up to a timeout and is retried a bounded number of times; timeouts, checksum
// (CRC) errors and retries are counted. A status packet whose error byte is set — overload, overheating, voltage,
// angle limit — is a ServoAlarm naming the servo and the errors; a servo that stays silent or garbled after the
// retries is a BusError. Both mean: stop, turn the torque off (hardware/robot/, docs/hardware.md "Safety").
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "hardware/dynamixel/control_table.h"
#include "hardware/dynamixel/packet.h"
#include "hardware/dynamixel/protocol1.h"
#include "hardware/dynamixel/protocol2.h"
#include "hardware/serial/serial_link.h"

namespace orcs::dynamixel {

/// How the driver talks: the protocol, how long it waits for an answer and how often it asks again.
struct BusOptions {
  Protocol protocol = Protocol::kV1;                    ///< what the servos speak
  std::chrono::microseconds timeout{20000};             ///< wait for one answer, µs (a reply takes < 1 ms at 1 Mbps)
  int retries = 2;                                      ///< further tries after a timeout or a checksum error
};

/// What the driver has seen over its life.
struct BusCounts {
  std::size_t instructions = 0;     ///< instruction packets sent (retries included)
  std::size_t replies = 0;          ///< intact status packets received
  std::size_t timeouts = 0;         ///< answers that did not come within the timeout
  std::size_t checksum_errors = 0;  ///< answers discarded for a wrong checksum (1.0) or CRC (2.0)
  std::size_t retries = 0;          ///< instructions sent again after a timeout or a checksum error
  std::size_t alarms = 0;           ///< status packets with the error byte set
};

/// The bus failed: a servo did not answer intact after the retries, or the port failed.
class BusError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A servo answered with its error byte set (overload, overheating, input voltage, angle limit, ...).
class ServoAlarm : public BusError {
 public:
  ServoAlarm(std::uint8_t id, std::uint8_t error, const std::string& text)
      : BusError("servo " + std::to_string(id) + " reports " + text), id_(id), error_(error) {}
  std::uint8_t id() const { return id_; }        ///< the servo
  std::uint8_t error() const { return error_; }  ///< its error byte as received

 private:
  std::uint8_t id_;
  std::uint8_t error_;
};

class DynamixelBus {
 public:
  DynamixelBus(std::unique_ptr<hardware::SerialLink> link, BusOptions options);

  /// Whether servo `id` answers a PING (after the retries); an alarm in its answer still counts as there.
  bool Ping(std::uint8_t id);
  /// The ids among first…last that answer a PING, each asked once (no retries: a missing id is the usual case).
  std::vector<std::uint8_t> Discover(std::uint8_t first, std::uint8_t last);
  /// `length` bytes of servo `id`'s control table from `address`.
  std::vector<std::uint8_t> Read(std::uint8_t id, std::uint16_t address, std::uint16_t length);
  /// Writes `data` at `address` of servo `id` and waits for its acknowledgement.
  void Write(std::uint8_t id, std::uint16_t address, std::span<const std::uint8_t> data);
  /// One SYNC_WRITE to several servos (no answer: broadcast).
  void SyncWrite(std::uint16_t address, std::uint16_t length, std::span<const SyncWriteEntry> entries);
  /// `length` bytes at `address` of each servo in `ids`, in order: one SYNC_READ in 2.0; in 1.0, which has none on
  /// the AX-12, one READ per servo.
  std::vector<std::vector<std::uint8_t>> SyncRead(std::span<const std::uint8_t> ids, std::uint16_t address,
                                                  std::uint16_t length);

  const BusCounts& counts() const { return counts_; }
  const BusOptions& options() const { return options_; }
  const std::string& port() const { return link_->path(); }

 private:
  // Sends `packet` and waits for the status packet of `id`; retries; throws BusError or ServoAlarm.
  Packet Exchange(const std::vector<std::uint8_t>& packet, std::uint8_t id, int retries);
  // Waits up to the timeout for the next status packet of `id`: nullopt on a timeout or a checksum error (counted).
  std::optional<Packet> AwaitStatus(std::uint8_t id);
  std::vector<DecodeEvent> Decode(std::span<const std::uint8_t> bytes);
  void Send(const std::vector<std::uint8_t>& packet);
  std::string ErrorTextOf(std::uint8_t error) const;

  std::unique_ptr<hardware::SerialLink> link_;  // the port
  BusOptions options_;                          // protocol, timeout, retries
  BusCounts counts_;                            // what happened so far
  std::variant<protocol1::Parser, protocol2::Parser> parser_;  // the answers' decoder, of the bus's protocol
  std::vector<Packet> pending_;                 // status packets decoded but not yet asked for
};

/// A register's little-endian bytes of `value` (size 1, 2 or 4), and back.
std::vector<std::uint8_t> LittleEndian(std::int64_t value, std::size_t size);
std::int64_t FromLittleEndian(std::span<const std::uint8_t> bytes);

}  // namespace orcs::dynamixel
