#include "hardware/robot/robot_session.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::hardware {

using dynamixel::ControlTable;
using dynamixel::FromLittleEndian;
using dynamixel::LittleEndian;
using dynamixel::SyncWriteEntry;
using Clock = std::chrono::steady_clock;

namespace {

// A signed register: AX-12 speed and load keep the sign in bit 10 (CCW below 1024, CW above); 2.0 is two's
// complement.
double SignedRegister(std::int64_t raw, std::size_t size, const ControlTable& table) {
  if (table.protocol == dynamixel::Protocol::kV1) return (raw & 0x400) ? -static_cast<double>(raw & 0x3FF) : static_cast<double>(raw & 0x3FF);
  const std::int64_t sign_bit = std::int64_t{1} << (8 * size - 1);
  return static_cast<double>((raw & sign_bit) ? raw - 2 * sign_bit : raw);
}

// The bytes from the first to the last state register the log reads.
struct StateWindow {
  std::uint16_t first = 0;   // address of the first byte read
  std::uint16_t length = 0;  // bytes read
};
StateWindow WindowOf(const ControlTable& t) {
  const std::uint16_t first = std::min({t.present_position, t.present_speed, t.present_load, t.present_voltage,
                                        t.present_temperature});
  const int last = std::max({t.present_position + t.position_size, t.present_speed + t.speed_size,
                             t.present_load + t.load_size, t.present_voltage + t.voltage_size,
                             t.present_temperature + 1});
  return {first, static_cast<std::uint16_t>(last - first)};
}

}  // namespace

std::string StopReasonName(StopReason reason) {
  switch (reason) {
    case StopReason::kFinished: return "finished";
    case StopReason::kInterrupted: return "interrupted";
    case StopReason::kBusError: return "bus error";
    case StopReason::kServoAlarm: return "servo alarm";
    case StopReason::kDeadlineStreak: return "missed deadlines";
  }
  return "unknown";
}

RobotSession::RobotSession(JointMap map, std::unique_ptr<dynamixel::DynamixelBus> bus, SessionOptions options)
    : map_(std::move(map)), bus_(std::move(bus)), options_(options) {
  if (!bus_ && !options_.dry_run) throw std::invalid_argument("RobotSession: no bus and no dry-run output");
}

RobotSession::~RobotSession() {
  if (torque_on_) TorqueOff();
}

void RobotSession::Print(const std::string& line) {
  if (options_.dry_run) *options_.dry_run << line << "\n";
}

void RobotSession::CheckServos() {
  if (!bus_) return;
  std::vector<std::string> missing;
  for (const JointMapping& joint : map_.joints) {
    if (!bus_->Ping(joint.id)) missing.push_back(std::to_string(joint.id) + " (" + joint.joint + ")");
  }
  if (missing.empty()) return;
  std::string list;
  for (const std::string& m : missing) list += (list.empty() ? "" : ", ") + m;
  throw InputError(map_.source, 0,
                   "servo" + std::string(missing.size() > 1 ? "s " : " ") + list + " did not answer on " +
                       bus_->port() + " at " + std::to_string(map_.baud) +
                       " baud (check the ids with a scan, the baud rate, the power and the cable)");
}

std::vector<double> RobotSession::FirstPose(CommandSource& source, const std::vector<double>& measured) const {
  std::vector<double> goal(map_.joints.size(), 0.0), torque(map_.joints.size(), 0.0);
  source.Commands(0.0, measured, goal, torque);
  for (std::size_t j = 0; j < goal.size(); ++j) goal[j] = ClampToLimits(map_.joints[j], goal[j]);
  return goal;
}

std::vector<double> RobotSession::ReadAngles() {
  RobotRow row;
  row.goal.assign(map_.joints.size(), 0.0);
  ReadState(row);
  return row.angle;
}

void RobotSession::TorqueOn() {
  const ControlTable& t = map_.servo;
  std::vector<SyncWriteEntry> limits, enable;
  sent_limits_.clear();
  std::ostringstream line;
  line << "SYNC_WRITE torque limit:";
  for (const JointMapping& joint : map_.joints) {
    const auto limit = static_cast<std::int64_t>(std::lround(joint.max_torque * t.torque_limit_full));
    limits.push_back({joint.id, LittleEndian(limit, 2)});
    sent_limits_.push_back(limit);
    enable.push_back({joint.id, {1}});
    line << " " << joint.joint << "(" << int{joint.id} << ")=" << limit;
  }
  torque_on_ = true;  // from here on every way out turns it off
  if (!bus_) {
    Print(line.str());
    Print("SYNC_WRITE torque enable: every joint = 1");
    return;
  }
  bus_->SyncWrite(t.torque_limit, 2, limits);
  bus_->SyncWrite(t.torque_enable, 1, enable);
}

void RobotSession::TorqueOff() noexcept {
  torque_on_ = false;
  try {
    std::vector<SyncWriteEntry> off;
    for (const JointMapping& joint : map_.joints) off.push_back({joint.id, {0}});
    if (!bus_) {
      Print("SYNC_WRITE torque enable: every joint = 0");
      return;
    }
    bus_->SyncWrite(map_.servo.torque_enable, 1, off);
  } catch (...) {
    // Nothing more can be done from here: the caller reports the run's own reason; the servos' own
    // protection (torque limit, alarm shutdown) remains.
  }
}

// The torque limits where the record changed them (before the goals, so that a servo has both when it moves),
// then every goal in one SYNC_WRITE.
void RobotSession::SendGoals(const std::vector<double>& goal, const std::vector<double>& torque) {
  const ControlTable& t = map_.servo;
  std::vector<SyncWriteEntry> limits, goals;
  std::ostringstream limit_line, goal_line;
  limit_line << "SYNC_WRITE torque limit:";
  goal_line << "SYNC_WRITE goal position:";
  for (std::size_t j = 0; j < map_.joints.size(); ++j) {
    const JointMapping& joint = map_.joints[j];
    const auto limit = static_cast<std::int64_t>(std::lround(torque[j] * t.torque_limit_full));
    if (limit != sent_limits_[j]) {
      limits.push_back({joint.id, LittleEndian(limit, 2)});
      limit_line << " " << joint.joint << "(" << int{joint.id} << ")=" << limit;
      sent_limits_[j] = limit;
    }
    // A limit may sit on the servo's last tick + 1 (the AX-12's +150° is tick 1024 of 0…1023): the register's range
    // is the last word.
    const std::int64_t ticks = std::clamp<std::int64_t>(ToTicks(joint, goal[j]), 0, t.max_tick);
    goals.push_back({joint.id, LittleEndian(ticks, t.position_size)});
    goal_line << " " << joint.joint << "(" << int{joint.id} << ")=" << ticks;
  }
  if (!bus_) {
    if (!limits.empty()) Print(limit_line.str());
    Print(goal_line.str());
    return;
  }
  if (!limits.empty()) bus_->SyncWrite(t.torque_limit, 2, limits);
  bus_->SyncWrite(t.goal_position, t.position_size, goals);
}

void RobotSession::ReadState(RobotRow& row) {
  const std::size_t n = map_.joints.size();
  row.angle.assign(n, 0.0);
  row.speed.assign(n, 0.0);
  row.load.assign(n, 0.0);
  row.voltage.assign(n, 0.0);
  row.temperature.assign(n, 0.0);
  if (!bus_) {
    row.angle = row.goal;  // a dry run has no robot: it "reaches" its commands
    return;
  }
  const ControlTable& t = map_.servo;
  const StateWindow window = WindowOf(t);
  std::vector<std::uint8_t> ids;
  for (const JointMapping& joint : map_.joints) ids.push_back(joint.id);
  const auto states = bus_->SyncRead(ids, window.first, window.length);
  for (std::size_t j = 0; j < n; ++j) {
    const JointMapping& joint = map_.joints[j];
    const auto field = [&](std::uint16_t address, std::size_t size) {
      return FromLittleEndian(std::span(states[j]).subspan(address - window.first, size));
    };
    row.angle[j] = ToDegrees(joint, field(t.present_position, t.position_size));
    row.speed[j] = joint.direction * SignedRegister(field(t.present_speed, t.speed_size), t.speed_size, t) * t.speed_unit;
    row.load[j] = SignedRegister(field(t.present_load, t.load_size), t.load_size, t);
    row.voltage[j] = static_cast<double>(field(t.present_voltage, t.voltage_size)) * t.voltage_unit;
    row.temperature[j] = static_cast<double>(field(t.present_temperature, 1));
  }
}

RobotRun RobotSession::Play(CommandSource& source, const std::atomic<bool>& interrupted) {
  const std::size_t n = map_.joints.size();
  RobotRun run;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options_.rate_hz));
  // The last period is the first at or after the source's duration, so that a record's last row (at any time, an
  // editor's receipt time) is sent; the period after it logs where that left the robot.
  const double last_period = std::ceil(source.duration() * options_.rate_hz - 1e-9) / options_.rate_hz;
  std::vector<double> command;  // what acts from the row on (row 0's is never applied: the robot's own angles)
  std::vector<double> wanted_goal(n, 0.0), wanted_torque(n, 0.0);  // the source's, before the limits
  std::vector<double> torque;  // what the servos' torque limits say: the map's limit until the record says more
  for (const JointMapping& joint : map_.joints) torque.push_back(joint.max_torque);
  int streak = 0;
  try {
    TorqueOn();
    const Clock::time_point start = Clock::now();
    for (std::size_t k = 0;; ++k) {
      const Clock::time_point due = start + period * static_cast<long>(k);
      if (options_.paced) std::this_thread::sleep_until(due);
      if (interrupted) {
        run.reason = StopReason::kInterrupted;
        run.message = "interrupted (Ctrl-C)";
        break;
      }
      const Clock::time_point began = Clock::now();
      RobotRow row;
      row.time = static_cast<double>(k) / options_.rate_hz;
      row.goal = k == 0 ? std::vector<double>(n, 0.0) : command;  // a dry run's robot "reaches" its command
      row.torque = torque;
      ReadState(row);
      if (k == 0) row.goal = command = row.angle;  // row 0's inputs never act: the robot's own angles stand in
      if (options_.twin) {
        if (k == 0) options_.twin->StartAt(row.angle);  // the twin starts where the robot is
        row.twin_angle = options_.twin->Angles();
      }
      if (row.time > last_period + 1e-9 || source.finished()) {  // the motion has ended: its last state is logged
        row.cycle = std::chrono::duration<double>(Clock::now() - began).count();
        if (options_.on_row) options_.on_row(row);
        run.rows.push_back(std::move(row));
        break;
      }
      source.Commands(row.time, row.angle, wanted_goal, wanted_torque);
      for (std::size_t j = 0; j < n; ++j) {
        command[j] = ClampToLimits(map_.joints[j], wanted_goal[j]);
        if (command[j] != wanted_goal[j]) ++run.clamped;
        torque[j] = std::clamp(wanted_torque[j], 0.0, map_.joints[j].max_torque);
      }
      row.command_delay = std::chrono::duration<double>(Clock::now() - due).count();
      SendGoals(command, torque);
      row.cycle = std::chrono::duration<double>(Clock::now() - began).count();
      if (options_.on_row) options_.on_row(row);
      // The twin gets the same command for the same period, after the robot (it must never delay it).
      if (options_.twin) options_.twin->Advance(command, torque, 1.0 / options_.rate_hz);
      run.rows.push_back(std::move(row));
      if (options_.paced && Clock::now() > due + period) {
        ++run.missed_deadlines;
        if (++streak >= options_.deadline_streak) {
          run.reason = StopReason::kDeadlineStreak;
          run.message = std::to_string(streak) + " control periods in a row overran their " +
                        text::FormatDouble(1000.0 / options_.rate_hz) +
                        " ms (lower --rate, or raise the baud rate)";
          break;
        }
      } else {
        streak = 0;
      }
    }
  } catch (const dynamixel::ServoAlarm& alarm) {
    run.reason = StopReason::kServoAlarm;
    run.message = alarm.what();
  } catch (const dynamixel::BusError& error) {
    run.reason = StopReason::kBusError;
    run.message = error.what();
  }
  TorqueOff();
  if (options_.twin) run.twin_status = options_.twin->status();
  return run;
}

std::string FormatRobotLog(const JointMap& map, const RobotRun& run, const std::vector<std::string>& comments,
                           LogSide side) {
  const bool twin = side == LogSide::kTwin;
  std::ostringstream out;
  out << (twin ? "# orcs-robot log: the simulated twin\n" : "# orcs-robot log\n");
  for (const std::string& comment : comments) out << "# " << comment << "\n";
  out << "# columns: time";
  const std::string sim = "/Sim/" + map.agent + "/";
  for (const JointMapping& joint : map.joints) {
    out << "," << sim << joint.joint << "/DesiredAngle," << sim << joint.joint << "/DesiredTorque," << sim
        << joint.joint << "/JointAngle";
  }
  if (!twin) {
    for (const JointMapping& joint : map.joints) {
      for (const char* q : {"Speed", "Load", "Voltage", "Temperature"}) out << ",/Robot/" << joint.joint << "/" << q;
    }
    out << ",/Robot/CommandDelay,/Robot/Cycle";
  }
  out << "\n";
  for (const RobotRow& row : run.rows) {
    out << text::FormatDouble(row.time);
    for (std::size_t j = 0; j < map.joints.size(); ++j) {
      out << "," << text::FormatDouble(row.goal[j]) << "," << text::FormatDouble(row.torque[j]) << ","
          << text::FormatDouble(twin ? row.twin_angle[j] : row.angle[j]);
    }
    if (twin) {
      out << "\n";
      continue;
    }
    for (std::size_t j = 0; j < map.joints.size(); ++j) {
      out << "," << text::FormatDouble(row.speed[j]) << "," << text::FormatDouble(row.load[j]) << ","
          << text::FormatDouble(row.voltage[j]) << "," << text::FormatDouble(row.temperature[j]);
    }
    out << "," << text::FormatDouble(row.command_delay) << "," << text::FormatDouble(row.cycle) << "\n";
  }
  return out.str();
}

std::string FormatBamLog(const JointMap& map, const RobotRun& run, const BamRig& rig) {
  if (map.joints.size() != 1) {
    throw InputError(map.source, 0, "BAM's log format holds one servo; this map has " +
                                        std::to_string(map.joints.size()) + " joints (use --out for the robot's log)");
  }
  constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
  nlohmann::json log;
  log["motor"] = std::string(map.servo.name);
  if (rig.mass) log["mass"] = *rig.mass;
  if (rig.length) log["length"] = *rig.length;
  if (rig.kp) log["kp"] = *rig.kp;
  if (!rig.trajectory.empty()) log["trajectory"] = rig.trajectory;
  if (run.rows.size() > 1) log["dt"] = run.rows[1].time - run.rows[0].time;
  double volts = 0.0;
  nlohmann::json entries = nlohmann::json::array();
  for (std::size_t k = 0; k < run.rows.size(); ++k) {
    const RobotRow& row = run.rows[k];
    // BAM's recorder reads the state, then sends the goal: the entry's goal is the one that acts after its row.
    const RobotRow& sent = run.rows[std::min(k + 1, run.rows.size() - 1)];
    entries.push_back({{"timestamp", row.time},
                       {"position", row.angle[0] * kRadiansPerDegree},
                       {"speed", row.speed[0] * kRadiansPerDegree},
                       {"load", row.load[0]},
                       {"input_volts", row.voltage[0]},
                       {"temp", row.temperature[0]},
                       {"goal_position", sent.goal[0] * kRadiansPerDegree},
                       {"torque_enable", sent.torque[0] > 0.0}});
    volts += row.voltage[0];
  }
  if (!run.rows.empty()) log["vin"] = volts / static_cast<double>(run.rows.size());
  log["entries"] = std::move(entries);
  return log.dump() + "\n";
}

}  // namespace orcs::hardware
