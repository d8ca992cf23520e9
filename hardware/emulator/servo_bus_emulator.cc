#include "hardware/emulator/servo_bus_emulator.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <variant>

#include "hardware/dynamixel/dynamixel_bus.h"
#include "hardware/dynamixel/protocol1.h"
#include "hardware/dynamixel/protocol2.h"

namespace orcs::hardware {

using dynamixel::FromLittleEndian;
using dynamixel::Instruction;
using dynamixel::LittleEndian;
using dynamixel::Protocol;

namespace {
constexpr int kPollMs = 5;                  // how often the thread looks at the stop flag
constexpr double kVoltage = 12.0;           // V: the emulated supply
constexpr std::uint8_t kTemperature = 35;   // °C: the emulated servos' temperature
constexpr std::uint8_t kRangeError1 = 0x08;        // Protocol 1.0's range error bit
constexpr std::uint8_t kInstructionError1 = 0x40;  // and its instruction error bit
constexpr std::uint8_t kAccessError2 = 7;          // Protocol 2.0's access error
constexpr std::uint8_t kInstructionError2 = 2;     // and its instruction error
}  // namespace

EmulatorOptions KinematicBus(const dynamixel::ControlTable& table, std::vector<std::uint8_t> ids,
                             double speed_deg_s) {
  EmulatorOptions options;
  options.table = table;
  options.ids = std::move(ids);
  options.speed_deg_s = speed_deg_s;
  return options;
}

struct ServoBusEmulator::Servo {
  std::uint8_t id = 0;                  // bus id
  std::vector<std::uint8_t> table;      // the control table's bytes
  double angle = 0.0;                   // shaft, degrees
  int corrupt = 0;                      // answers still to garble
  bool silent = false;                  // answers nothing
  std::uint8_t alarm = 0;               // error byte of every answer
  std::chrono::steady_clock::time_point moved = std::chrono::steady_clock::now();  // last shaft update
};

ServoBusEmulator::ServoBusEmulator(EmulatorOptions options) : options_(std::move(options)) {
  std::array<char, 256> name{};
  if (::openpty(&master_, &slave_, name.data(), nullptr, nullptr) != 0) {
    throw std::runtime_error(std::string("servo-bus emulator: cannot open a pseudo-terminal: ") + std::strerror(errno));
  }
  termios mode{};
  ::tcgetattr(slave_, &mode);
  ::cfmakeraw(&mode);  // bytes as sent: no echo, no line editing, no CR/LF translation
  ::tcsetattr(slave_, TCSANOW, &mode);
  port_ = name.data();
  const dynamixel::ControlTable& t = options_.table;
  for (std::uint8_t id : options_.ids) {
    auto servo = std::make_unique<Servo>();
    servo->id = id;
    servo->table.assign(t.table_size, 0);
    const auto model = LittleEndian(t.model_number, 2);
    std::copy(model.begin(), model.end(), servo->table.begin());
    servo->table[t.protocol == Protocol::kV1 ? 3 : 7] = id;
    const auto goal = LittleEndian(t.center_tick, t.position_size);
    std::copy(goal.begin(), goal.end(), servo->table.begin() + t.goal_position);
    const auto limit = LittleEndian(t.torque_limit_full, 2);  // factory default: all the torque there is
    std::copy(limit.begin(), limit.end(), servo->table.begin() + t.torque_limit);
    servos_[id] = std::move(servo);
  }
  thread_ = std::thread([this] { Serve(); });
}

ServoBusEmulator::~ServoBusEmulator() {
  stop_ = true;
  thread_.join();
  ::close(master_);
  ::close(slave_);
}

void ServoBusEmulator::CorruptAnswers(std::uint8_t id, int count) {
  std::lock_guard lock(mutex_);
  Find(id)->corrupt = count;
}
void ServoBusEmulator::Silence(std::uint8_t id, bool silent) {
  std::lock_guard lock(mutex_);
  Find(id)->silent = silent;
}
void ServoBusEmulator::RaiseAlarm(std::uint8_t id, std::uint8_t error) {
  std::lock_guard lock(mutex_);
  Find(id)->alarm = error;
}
std::vector<AppliedWrite> ServoBusEmulator::writes() const {
  std::lock_guard lock(mutex_);
  return writes_;
}
double ServoBusEmulator::Angle(std::uint8_t id) const {
  std::lock_guard lock(mutex_);
  return servos_.at(id)->angle;
}
bool ServoBusEmulator::TorqueOn(std::uint8_t id) const {
  std::lock_guard lock(mutex_);
  return servos_.at(id)->table[options_.table.torque_enable] != 0;
}

ServoBusEmulator::Servo* ServoBusEmulator::Find(std::uint8_t id) {
  auto it = servos_.find(id);
  if (it == servos_.end()) throw std::invalid_argument("servo-bus emulator: no servo " + std::to_string(id));
  return it->second.get();
}

void ServoBusEmulator::Serve() {
  std::variant<dynamixel::protocol1::Parser, dynamixel::protocol2::Parser> parser =
      options_.table.protocol == Protocol::kV1
          ? decltype(parser)(dynamixel::protocol1::Parser(dynamixel::PacketKind::kInstruction))
          : decltype(parser)(dynamixel::protocol2::Parser());
  std::array<std::uint8_t, 256> chunk{};
  while (!stop_) {
    pollfd wait{master_, POLLIN, 0};
    if (::poll(&wait, 1, kPollMs) <= 0 || !(wait.revents & POLLIN)) continue;
    const ssize_t n = ::read(master_, chunk.data(), chunk.size());
    if (n <= 0) continue;
    const auto events = std::visit([&](auto& p) { return p.Feed(std::span(chunk.data(), static_cast<std::size_t>(n))); },
                                   parser);
    for (const dynamixel::DecodeEvent& event : events) {
      if (event.outcome == dynamixel::DecodeOutcome::kChecksumError) ++checksum_errors_;
      if (event.outcome != dynamixel::DecodeOutcome::kPacket ||
          event.packet.kind != dynamixel::PacketKind::kInstruction) {
        continue;
      }
      ++instructions_;
      std::lock_guard lock(mutex_);
      MoveShafts();
      const dynamixel::Packet& p = event.packet;
      const bool v1 = options_.table.protocol == Protocol::kV1;
      const std::size_t address_size = v1 ? 1 : 2;
      const auto address_at = [&](std::size_t i) {
        return static_cast<std::uint16_t>(FromLittleEndian(std::span(p.params).subspan(i, address_size)));
      };
      const bool broadcast = p.id == dynamixel::kBroadcastId;
      Servo* servo = broadcast || !servos_.count(p.id) ? nullptr : servos_[p.id].get();
      switch (static_cast<Instruction>(p.instruction)) {
        case Instruction::kPing:
          if (servo) Reply(*servo, v1 ? std::vector<std::uint8_t>{} : [&] {
            auto model = LittleEndian(options_.table.model_number, 2);
            model.push_back(1);  // firmware version
            return model;
          }());
          break;
        case Instruction::kRead: {
          if (!servo || p.params.size() != 2 * address_size) break;
          bool ok = true;
          auto bytes = ReadTable(*servo, address_at(0), address_at(address_size), ok);
          Reply(*servo, ok ? bytes : std::vector<std::uint8_t>{}, ok ? 0 : (v1 ? kRangeError1 : kAccessError2));
          break;
        }
        case Instruction::kWrite:
          if (!servo || p.params.size() <= address_size) break;
          ApplyWrite(*servo, address_at(0), std::vector<std::uint8_t>(p.params.begin() + address_size, p.params.end()));
          if (address_at(0) == options_.table.goal_position) AdvanceModel();
          Reply(*servo, {});
          break;
        case Instruction::kSyncWrite: {
          if (p.params.size() < 2 * address_size) break;
          const std::uint16_t address = address_at(0);
          const std::size_t length = address_at(address_size);
          for (std::size_t i = 2 * address_size; i + 1 + length <= p.params.size(); i += 1 + length) {
            auto it = servos_.find(p.params[i]);
            if (it == servos_.end()) continue;
            ApplyWrite(*it->second, address,
                       std::vector<std::uint8_t>(p.params.begin() + i + 1, p.params.begin() + i + 1 + length));
          }
          if (address == options_.table.goal_position) AdvanceModel();
          break;
        }
        case Instruction::kSyncRead: {
          if (v1 || p.params.size() < 4) break;
          const std::uint16_t address = address_at(0);
          const std::uint16_t length = address_at(2);
          for (std::size_t i = 4; i < p.params.size(); ++i) {
            auto it = servos_.find(p.params[i]);
            if (it == servos_.end()) continue;
            bool ok = true;
            auto bytes = ReadTable(*it->second, address, length, ok);
            Reply(*it->second, ok ? bytes : std::vector<std::uint8_t>{}, ok ? 0 : kAccessError2);
          }
          break;
        }
        default:
          if (servo) Reply(*servo, {}, v1 ? kInstructionError1 : kInstructionError2);
      }
    }
  }
}

void ServoBusEmulator::Reply(Servo& servo, std::vector<std::uint8_t> params, std::uint8_t error) {
  if (servo.silent) return;
  const std::uint8_t status = static_cast<std::uint8_t>(error | servo.alarm);
  std::vector<std::uint8_t> packet = options_.table.protocol == Protocol::kV1
                                         ? dynamixel::protocol1::EncodeStatus(servo.id, status, params)
                                         : dynamixel::protocol2::EncodeStatus(servo.id, status, params);
  if (servo.corrupt > 0) {
    --servo.corrupt;
    packet.back() ^= 0x5A;  // the checksum's (the CRC's high) byte
  }
  std::size_t done = 0;
  while (done < packet.size()) {
    const ssize_t n = ::write(master_, packet.data() + done, packet.size() - done);
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

void ServoBusEmulator::ApplyWrite(Servo& servo, std::uint16_t address, std::vector<std::uint8_t> bytes) {
  if (address + bytes.size() > servo.table.size()) return;
  std::copy(bytes.begin(), bytes.end(), servo.table.begin() + address);
  writes_.push_back({servo.id, address, std::move(bytes)});
  written_.notify_all();
}

bool ServoBusEmulator::AwaitAllTorqueOff(std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  return written_.wait_for(lock, timeout, [&] {
    return std::all_of(servos_.begin(), servos_.end(),
                       [&](const auto& entry) { return entry.second->table[options_.table.torque_enable] == 0; });
  });
}

std::vector<std::uint8_t> ServoBusEmulator::ReadTable(Servo& servo, std::uint16_t address, std::uint16_t length,
                                                      bool& ok) {
  ok = address + length <= servo.table.size();
  if (!ok) return {};
  return std::vector<std::uint8_t>(servo.table.begin() + address, servo.table.begin() + address + length);
}

// Each shaft moves towards its goal at the no-load speed while its torque is on; the present registers follow.
// With a ShaftModel the shafts move only when it advances (AdvanceModel); here only the registers are refreshed.
void ServoBusEmulator::MoveShafts() {
  const dynamixel::ControlTable& t = options_.table;
  const auto now = std::chrono::steady_clock::now();
  std::size_t index = 0;
  for (auto& [id, servo] : servos_) {
    const double dt = std::chrono::duration<double>(now - servo->moved).count();
    servo->moved = now;
    double speed = 0.0;
    if (options_.shafts) {
      servo->angle = options_.shafts->Angle(index);
      speed = options_.shafts->Speed(index);
    } else if (servo->table[t.torque_enable] != 0) {
      const auto goal_ticks = FromLittleEndian(std::span(servo->table).subspan(t.goal_position, t.position_size));
      const double goal = static_cast<double>(goal_ticks - t.center_tick) * t.degrees_per_tick;
      const double step = std::clamp(goal - servo->angle, -options_.speed_deg_s * dt, options_.speed_deg_s * dt);
      servo->angle += step;
      speed = dt > 0 ? step / dt : 0.0;
    }
    WriteShaftState(*servo, speed);
    ++index;
  }
}

// One control period under the goals just written: the model takes them, then moves on.
void ServoBusEmulator::AdvanceModel() {
  if (!options_.shafts) return;
  const dynamixel::ControlTable& t = options_.table;
  std::size_t index = 0;
  for (auto& [id, servo] : servos_) {
    const auto goal_ticks = FromLittleEndian(std::span(servo->table).subspan(t.goal_position, t.position_size));
    const auto limit = FromLittleEndian(std::span(servo->table).subspan(t.torque_limit, 2));
    const double torque = servo->table[t.torque_enable] != 0
                              ? std::clamp(static_cast<double>(limit) / t.torque_limit_full, 0.0, 1.0)
                              : 0.0;
    options_.shafts->Command(index++, static_cast<double>(goal_ticks - t.center_tick) * t.degrees_per_tick, torque);
  }
  options_.shafts->Advance(options_.period_s);
  MoveShafts();
}

void ServoBusEmulator::WriteShaftState(Servo& servo, double speed) {
  const dynamixel::ControlTable& t = options_.table;
  const auto put = [&](std::uint16_t address, std::int64_t value, std::size_t size) {
    const auto bytes = LittleEndian(value, size);
    std::copy(bytes.begin(), bytes.end(), servo.table.begin() + address);
  };
  put(t.present_position, std::lround(servo.angle / t.degrees_per_tick) + t.center_tick, t.position_size);
  const long speed_units = std::lround(std::abs(speed) / t.speed_unit);
  put(t.present_speed,
      t.protocol == Protocol::kV1 ? (speed_units | (speed < 0 ? 0x400 : 0)) : std::lround(speed / t.speed_unit),
      t.speed_size);
  put(t.present_voltage, std::lround(kVoltage / t.voltage_unit), t.voltage_size);
  servo.table[t.present_temperature] = kTemperature;
}

}  // namespace orcs::hardware
