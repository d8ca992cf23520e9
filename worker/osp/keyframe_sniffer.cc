#include "worker/osp/keyframe_sniffer.h"

#include <cmath>

#include "model/aseries/value_range.h"

namespace orcs::osp {

KeyframeSniffer::KeyframeSniffer(int motor_count, std::function<Clock::time_point()> now)
    : motor_count_(motor_count), now_(std::move(now)) {
  for (int m = 0; m < motor_count_; ++m) {
    current_.push_back(0.0);
    current_.push_back(aseries::kDefaultDesiredTorqueRaw);
  }
  record_.motor_count = motor_count_;
}

void KeyframeSniffer::Set(std::span<const double> angles, std::span<const double> torques) {
  const Clock::time_point received = now_();
  if (record_.frames.empty()) first_command_ = received;
  for (std::size_t m = 0; m < current_.size() / 2 && m < angles.size() && m < torques.size(); ++m) {
    current_[2 * m] = angles[m];
    current_[2 * m + 1] = torques[m];
  }
  const auto since_first = std::chrono::duration_cast<std::chrono::microseconds>(received - first_command_);
  control::Keyframe row;
  row.time_ms = static_cast<double>(since_first.count()) / 1000.0;
  row.inputs = current_;
  row.line = static_cast<int>(record_.frames.size()) + 1;
  record_.frames.push_back(std::move(row));
}

}  // namespace orcs::osp
