// One run of a controller on the physical robot, safety first (docs/hardware.md, "Safety"): every command is
// clamped to the joint map's limits before anything is sent; the run stops with the torque off on Ctrl-C (the
// caller's flag, checked every control period), a bus error, a servo alarm or a streak of missed deadlines, and
// says why. Each control period reads the servos' state and logs it beside the command that acted until then,
// so the log is a measured run orcs-gap reads as it stands (docs/gap_measured_data.md).
//
// Without a bus (a dry run) nothing is sent: each packet that would be is printed instead, and the log's angles
// are the commands.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardware/dynamixel/dynamixel_bus.h"
#include "hardware/robot/command_source.h"
#include "hardware/robot/joint_map.h"
#include "hardware/robot/simulated_twin.h"

namespace orcs::hardware {

struct RobotRow;

/// How a run is paced and when it gives up.
struct SessionOptions {
  double rate_hz = 50.0;         ///< control rate, Hz: one command and one state read per period
  int deadline_streak = 5;       ///< consecutive periods that overrun their deadline before the run stops
  std::ostream* dry_run = nullptr;  ///< where a dry run prints what would be sent (no bus)
  SimulatedTwin* twin = nullptr;    ///< the simulated twin fed the same commands each period, or none
  bool paced = true;                ///< false: no waiting between periods (an emulated world advancing per command)
  /// Called with each control period's row once its command went out (and with the last row), the twin still at
  /// the row's time: what orcs-robot --view records. Runs in the control loop, after the robot's bus traffic.
  std::function<void(const RobotRow&)> on_row;
};

/// Why a run ended.
enum class StopReason {
  kFinished,        ///< the controller's motion ended
  kInterrupted,     ///< Ctrl-C (SIGINT/SIGTERM)
  kBusError,        ///< a servo did not answer intact, or the port failed
  kServoAlarm,      ///< a servo reported overload, overheating, voltage, angle limit, ...
  kDeadlineStreak,  ///< too many control periods in a row overran
};
std::string StopReasonName(StopReason reason);

/// One control period's row of the log.
struct RobotRow {
  double time = 0.0;                   ///< s, nominal: period · row
  std::vector<double> goal;            ///< per joint: the command that acted until this row, degrees (clamped)
  std::vector<double> torque;          ///< per joint: its torque, 0…1 (0 = limp)
  std::vector<double> angle;           ///< per joint: the measured angle, degrees
  std::vector<double> twin_angle;      ///< per joint: the twin's angle, degrees (empty without a twin)
  std::vector<double> speed;           ///< per joint: the servo's speed, °/s
  std::vector<double> load;            ///< per joint: the servo's load register, raw
  std::vector<double> voltage;         ///< per joint: supply voltage, V
  std::vector<double> temperature;     ///< per joint: °C
  double command_delay = 0.0;          ///< s: how late after the row's nominal time the command went out
  double cycle = 0.0;                  ///< s: the bus time of this period (command + reads)
};

/// What a run did.
struct RobotRun {
  StopReason reason = StopReason::kFinished;  ///< why it ended
  std::string message;                        ///< the reason in words (the alarm's text, the bus error)
  std::vector<RobotRow> rows;                 ///< the log, one row per control period
  std::size_t clamped = 0;                    ///< commands clamped to a joint's limits
  std::size_t missed_deadlines = 0;           ///< periods that overran
  std::string twin_status;                    ///< why the twin stopped early, "" when it ran to the end
};

class RobotSession {
 public:
  /// `bus` may be null: a dry run, printing to options.dry_run.
  RobotSession(JointMap map, std::unique_ptr<dynamixel::DynamixelBus> bus, SessionOptions options);
  /// Turns the torque off if it is on.
  ~RobotSession();

  /// Pings every servo of the map; throws InputError listing the ids that do not answer.
  void CheckServos();
  /// The joints' present angles, degrees (a dry run: 0 each).
  std::vector<double> ReadAngles();
  /// The source's first commands for the robot at `measured` (degrees), clamped to the limits: where the robot
  /// goes when torque comes on.
  std::vector<double> FirstPose(CommandSource& source, const std::vector<double>& measured) const;
  /// Plays `source` until its duration ends or something stops it: torque on, one period per 1/rate_hz, torque off
  /// at the end whatever the reason. `interrupted` is checked every period.
  RobotRun Play(CommandSource& source, const std::atomic<bool>& interrupted);
  /// Every joint limp; never throws (it is what happens on every error).
  void TorqueOff() noexcept;

  const JointMap& map() const { return map_; }
  const dynamixel::DynamixelBus* bus() const { return bus_.get(); }

 private:
  void TorqueOn();
  void SendGoals(const std::vector<double>& goal, const std::vector<double>& torque);
  void ReadState(RobotRow& row);
  void Print(const std::string& line);

  JointMap map_;                                    // joints, ids, limits
  std::unique_ptr<dynamixel::DynamixelBus> bus_;    // null in a dry run
  SessionOptions options_;                          // rate, deadline streak, dry-run output
  bool torque_on_ = false;                          // whether TorqueOn ran without TorqueOff since
  std::vector<std::int64_t> sent_limits_;           // the torque limit registers as last written, per joint
};

/// Which side of a run a log shows: the robot's measured angles, or its twin's simulated ones.
enum class LogSide { kRobot, kTwin };

/// The run as a measured run CSV (orcs's native log, docs/gap_measured_data.md): time, then per joint
/// /Sim/<agent>/<joint>/DesiredAngle, DesiredTorque, JointAngle, then the servo's other readings
/// (/Robot/<joint>/Speed, Load, Voltage, Temperature) and the bus's timing (/Robot/CommandDelay, /Robot/Cycle).
/// The twin's log (LogSide::kTwin) has the same rows and commands with the twin's angles, and no /Robot/ columns.
std::string FormatRobotLog(const JointMap& map, const RobotRun& run, const std::vector<std::string>& comments,
                           LogSide side = LogSide::kRobot);

/// What BAM's log says of the rig besides the run (model/identify/bam_log.h): written where given.
struct BamRig {
  std::optional<double> mass;    ///< kg, the load
  std::optional<double> length;  ///< m, the load's distance from the axis
  std::optional<double> kp;      ///< the servo's firmware P gain during the run
  std::string trajectory;        ///< the motion's name
};

/// A one-joint run in BAM's JSON log format (Rhoban's recorder): the rig (`motor` the servo's name, `dt` the period,
/// `vin` the mean supply voltage, and `mass`, `length`, `kp`, `trajectory` where `rig` has them) and one entry per
/// row — timestamp s, position rad, speed rad/s, load, input_volts V, temp °C, goal_position rad, torque_enable —
/// with BAM's timing: an entry's goal is the one sent after its state was read. Throws InputError for a map of more
/// than one joint (a BAM log is one servo's).
std::string FormatBamLog(const JointMap& map, const RobotRun& run, const BamRig& rig);

}  // namespace orcs::hardware
