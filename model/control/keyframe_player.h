// Plays a keyframe record (keyframe_record.h) into one agent's inputs, driven by simulated time — never by the
// wall clock — so a replay is the same at any speed (spec/osp.md). Before each simulation step the caller
// passes the step's start time; the latest row whose time is not after it is written to the agent's
// DesiredAngle and DesiredTorque values. Before the first row takes effect the inputs keep their values.
#pragma once

#include <string>
#include <vector>

#include "model/control/controller.h"
#include "model/control/keyframe_record.h"
#include "model/core/value.h"
#include "model/core/variable_repository.h"

namespace orcs::control {

class KeyframePlayer : public Controller {
 public:
  /// Binds `record` to agent `agent`'s motors (names in motor order, e.g. "Right/Knee"), whose values must be
  /// registered in `values` (/Sim/<agent>/<motor>/DesiredAngle, DesiredTorque, MinAngle, MaxAngle). Angles
  /// outside a joint's [MinAngle, MaxAngle] and torques outside −1…1 are clamped; each input that needed it
  /// gets one warning (warnings()). Throws InputError when the record's motor count differs from the agent's.
  KeyframePlayer(KeyframeRecord record, const std::string& agent, const std::vector<std::string>& motors,
                 VariableRepository& values);

  /// Back to before the first row (call after the simulation's Reset).
  void Reset() override { next_row_ = 0; }

  /// Writes the latest row whose time (ms) is at most `time_seconds` × 1000, if it is not written yet.
  void Apply(double time_seconds);
  void Update(double time_seconds) override { Apply(time_seconds); }

  /// One line per clamped input: "file:line: warning: ...".
  const std::vector<std::string>& warnings() const { return warnings_; }
  const KeyframeRecord& record() const { return record_; }
  /// Simulated seconds of the last row.
  double duration() const { return record_.frames.back().time_ms / 1000.0; }

 private:
  void ClampToRanges(const std::vector<std::string>& motors, const std::string& agent,
                     const VariableRepository& values);

  KeyframeRecord record_;
  std::vector<Value*> inputs_;  // in input order: DesiredAngle, DesiredTorque per motor
  size_t next_row_ = 0;         // first row not yet reached
  std::vector<std::string> warnings_;
};

}  // namespace orcs::control
