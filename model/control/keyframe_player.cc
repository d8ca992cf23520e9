#include "model/control/keyframe_player.h"

#include <algorithm>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::control {
namespace {

// Row times are whole or fractional milliseconds; simulated time is a sum of steps. The tolerance keeps a
// row at 30 ms from missing the step that starts at 0.03 s = 29.999999999999996 ms.
constexpr double kTimeToleranceMs = 1e-6;

std::string MotorPath(const std::string& agent, const std::string& motor, const char* value) {
  return "/Sim/" + agent + "/" + motor + "/" + value;
}

}  // namespace

KeyframePlayer::KeyframePlayer(KeyframeRecord record, const std::string& agent,
                               const std::vector<std::string>& motors, VariableRepository& values)
    : record_(std::move(record)) {
  if (record_.motor_count != static_cast<int>(motors.size())) {
    throw InputError(record_.source, 0,
                     "the record has inputs for " + Motors(record_.motor_count) + ", agent '" +
                         agent + "' has " + std::to_string(motors.size()));
  }
  for (const std::string& motor : motors) {
    inputs_.push_back(&values.Get(MotorPath(agent, motor, "DesiredAngle")));
    inputs_.push_back(&values.Get(MotorPath(agent, motor, "DesiredTorque")));
  }
  ClampToRanges(motors, agent, values);
}

void KeyframePlayer::ClampToRanges(const std::vector<std::string>& motors, const std::string& agent,
                                   const VariableRepository& values) {
  for (size_t m = 0; m < motors.size(); ++m) {
    const double low[2] = {values.Get(MotorPath(agent, motors[m], "MinAngle")).as_double(), -1.0};
    const double high[2] = {values.Get(MotorPath(agent, motors[m], "MaxAngle")).as_double(), 1.0};
    static constexpr const char* kNames[2] = {"DesiredAngle", "DesiredTorque"};
    for (size_t k = 0; k < 2; ++k) {
      bool warned = false;
      for (Keyframe& frame : record_.frames) {
        double& input = frame.inputs[2 * m + k];
        const double clamped = std::clamp(input, low[k], high[k]);
        if (clamped == input) continue;
        if (!warned) {
          warnings_.push_back(record_.source + ":" + std::to_string(frame.line) + ": warning: " + motors[m] + "/" +
                              kNames[k] + " " + text::FormatDouble(input) + " is outside " +
                              text::FormatDouble(low[k]) + "…" + text::FormatDouble(high[k]) +
                              "; clamped here and wherever else it is outside");
          warned = true;
        }
        input = clamped;
      }
    }
  }
}

void KeyframePlayer::Apply(double time_seconds) {
  const double now_ms = time_seconds * 1000.0 + kTimeToleranceMs;
  size_t reached = next_row_;
  while (reached < record_.frames.size() && record_.frames[reached].time_ms <= now_ms) ++reached;
  if (reached == next_row_) return;  // no new row: leave the inputs to whoever else writes them
  next_row_ = reached;
  const Keyframe& row = record_.frames[reached - 1];
  for (size_t i = 0; i < inputs_.size(); ++i) inputs_[i]->Set(row.inputs[i]);
}

}  // namespace orcs::control
