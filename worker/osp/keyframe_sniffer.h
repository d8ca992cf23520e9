// The KeyFrameSniffer (spec/osp.md): an ODCP motor target that records instead of moving a robot. A motion
// editor sends its set-motors commands to the sniffer's ODCP server as it would to the simulator; each command
// becomes one keyframe row — its receipt time in milliseconds since the first command (so the record starts at
// 0 ms, not after however long the editor waited before sending), then every motor's goal angle (degrees) and raw
// DesiredTorque (0…1). get-motors answers with the last command (the A-Series defaults before the first one).
// Recording is finished by a disconnect after at least one command (a disconnect before any is taken as the
// editor probing and ignored). The record is the raw layout that `orcs-sim -play AGENT FILE` replays.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "model/control/keyframe_record.h"
#include "worker/osp/odcp_server.h"

namespace orcs::osp {

class KeyframeSniffer : public OdcpMotors {
 public:
  using Clock = std::chrono::steady_clock;

  /// Records for `motor_count` motors (21 for the A-Series); `now` is the clock receipt times are read from.
  explicit KeyframeSniffer(int motor_count, std::function<Clock::time_point()> now = Clock::now);

  int motor_count() const override { return motor_count_; }
  double angle(int m) const override { return current_[2 * static_cast<std::size_t>(m)]; }
  double torque(int m) const override { return current_[2 * static_cast<std::size_t>(m) + 1]; }
  /// Appends a row at the receipt time (ms since the first command, to the microsecond).
  void Set(std::span<const double> angles, std::span<const double> torques) override;
  void OnDisconnect() override { finished_ = finished_ || !record_.frames.empty(); }

  /// A disconnect came after at least one command.
  bool finished() const { return finished_; }
  /// The rows so far, in input order per row (angle, torque per motor).
  const control::KeyframeRecord& record() const { return record_; }

 private:
  int motor_count_ = 0;                          // motors per row
  std::function<Clock::time_point()> now_;       // the receipt clock
  std::vector<double> current_;                  // the last command in input order (defaults before the first)
  control::KeyframeRecord record_;               // rows so far
  Clock::time_point first_command_;              // receipt time of the first command (row time 0)
  bool finished_ = false;                        // a disconnect came after at least one command
};

}  // namespace orcs::osp
