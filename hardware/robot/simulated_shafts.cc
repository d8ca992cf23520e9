#include "hardware/robot/simulated_shafts.h"

#include "model/core/error.h"

namespace orcs::hardware {

SimulatedShafts::SimulatedShafts(const std::string& environment_file, const JointMap& map,
                                 const std::vector<std::string>& value_files)
    : world_(environment_file, map, value_files),
      goals_(map.joints.size(), 0.0),
      torques_(map.joints.size(), 0.0),
      angles_(world_.Angles()),
      speeds_(map.joints.size(), 0.0) {
  for (std::size_t j = 1; j < map.joints.size(); ++j) {
    if (map.joints[j].id <= map.joints[j - 1].id) {
      throw InputError(map.source, 0, "the emulator's simulated shafts need the joints in ascending id order ('" +
                                          map.joints[j].joint + "' has id " + std::to_string(map.joints[j].id) +
                                          " after " + std::to_string(map.joints[j - 1].id) + ")");
    }
  }
}

void SimulatedShafts::Command(std::size_t index, double goal_deg, double torque) {
  goals_.at(index) = goal_deg;
  torques_.at(index) = torque;
}

void SimulatedShafts::Advance(double seconds) {
  world_.Advance(goals_, torques_, seconds);
  const std::vector<double> now = world_.Angles();
  for (std::size_t j = 0; j < now.size(); ++j) speeds_[j] = (now[j] - angles_[j]) / seconds;
  angles_ = now;
}

}  // namespace orcs::hardware
