// A bus of emulated Dynamixel servos on one end of a pseudo-terminal, written from the ROBOTIS protocol
// documentation, so that the bus driver, orcs-robot and their safety rules are tested on any machine through a real
// terminal device (docs/hardware.md, "The servo-bus emulator").
//
// It answers PING, READ, WRITE, SYNC_WRITE and (2.0) SYNC_READ as N servos of one model (the AX-12+'s or the
// XL330's control table) and keeps a log of every write it applied. Faults are switched on from the test: replies
// with a wrong checksum, a silent servo, an alarm in the error byte. Each shaft moves towards its goal at the
// servo's no-load speed while its torque is on — a kinematic shaft — unless a ShaftModel (orcs's simulation of
// the robot, with hidden effects) turns them (shaft_model.h).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hardware/dynamixel/control_table.h"
#include "hardware/emulator/shaft_model.h"

namespace orcs::hardware {

/// One write the emulator applied to a servo's control table (WRITE or its part of a SYNC_WRITE).
struct AppliedWrite {
  std::uint8_t id = 0;                 ///< the servo
  std::uint16_t address = 0;           ///< first byte written
  std::vector<std::uint8_t> bytes;     ///< what was written
};

/// What the emulator emulates.
struct EmulatorOptions {
  dynamixel::ControlTable table = dynamixel::kAx12;  ///< the servo model (and so the protocol)
  std::vector<std::uint8_t> ids;                      ///< the servos on the bus
  double speed_deg_s = 684.0;                         ///< shaft speed towards the goal, °/s (AX-12 no-load: 114 rpm)
  /// The shafts' physics instead of the kinematic ones (null: kinematic, by the wall clock). It advances by
  /// `period_s` after each instruction that writes goal positions (a SYNC_WRITE of the goals: one control period).
  std::shared_ptr<ShaftModel> shafts;
  double period_s = 0.01;                             ///< s, the control period `shafts` advances per goal write
};

/// A bus of `ids` with kinematic shafts moving at `speed_deg_s`.
EmulatorOptions KinematicBus(const dynamixel::ControlTable& table, std::vector<std::uint8_t> ids,
                             double speed_deg_s = 684.0);

class ServoBusEmulator {
 public:
  /// Opens a pseudo-terminal pair and starts answering on it. Throws std::runtime_error when no pseudo-terminal
  /// can be opened.
  explicit ServoBusEmulator(EmulatorOptions options);
  /// Stops answering and closes the pseudo-terminal.
  ~ServoBusEmulator();
  ServoBusEmulator(const ServoBusEmulator&) = delete;
  ServoBusEmulator& operator=(const ServoBusEmulator&) = delete;

  /// The terminal device to open as the bus's serial port (/dev/pts/N).
  const std::string& port() const { return port_; }

  /// The next `count` answers of servo `id` carry a wrong checksum (CRC).
  void CorruptAnswers(std::uint8_t id, int count);
  /// Servo `id` answers nothing while `silent` (a loose cable, a wrong id).
  void Silence(std::uint8_t id, bool silent);
  /// From now on every answer of servo `id` carries `error` in its error byte (overload, overheating, ...).
  void RaiseAlarm(std::uint8_t id, std::uint8_t error);

  /// Every write applied so far, in order.
  std::vector<AppliedWrite> writes() const;
  /// Servo `id`'s shaft angle, degrees, and whether its torque is on.
  double Angle(std::uint8_t id) const;
  bool TorqueOn(std::uint8_t id) const;
  /// Waits up to `timeout` until every servo's torque is off (the last packets of a program that has ended may
  /// still be in the terminal's buffer); whether it is.
  bool AwaitAllTorqueOff(std::chrono::milliseconds timeout) const;
  /// Instruction packets received intact, and those with a wrong checksum (CRC).
  std::size_t instructions() const { return instructions_; }
  std::size_t checksum_errors() const { return checksum_errors_; }

 private:
  struct Servo;
  void Serve();
  void Reply(Servo& servo, std::vector<std::uint8_t> params, std::uint8_t error = 0);
  void ApplyWrite(Servo& servo, std::uint16_t address, std::vector<std::uint8_t> bytes);
  std::vector<std::uint8_t> ReadTable(Servo& servo, std::uint16_t address, std::uint16_t length, bool& ok);
  void MoveShafts();
  void WriteShaftState(Servo& servo, double speed);
  void AdvanceModel();
  Servo* Find(std::uint8_t id);

  EmulatorOptions options_;
  std::string port_;                  // the terminal's device (the driver's side)
  int master_ = -1;                   // the emulator's side
  int slave_ = -1;                    // held open so that the master never reads EIO between the driver's opens
  mutable std::mutex mutex_;          // guards the servos and the log
  mutable std::condition_variable written_;  // notified after every applied write
  std::map<std::uint8_t, std::unique_ptr<Servo>> servos_;  // by id
  std::vector<AppliedWrite> writes_;
  std::atomic<std::size_t> instructions_{0};
  std::atomic<std::size_t> checksum_errors_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace orcs::hardware
