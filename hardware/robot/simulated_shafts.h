// orcs's simulation of the robot behind the servo-bus emulator's shafts (emulator/shaft_model.h): the joint map's
// joints in an environment, with value files applied — the servo model's parameters, and hidden effects that a
// recording through the bus should let orcs-gap name (docs/hardware.md, "The servo-bus emulator").
#pragma once

#include <string>
#include <vector>

#include "hardware/emulator/shaft_model.h"
#include "hardware/robot/joint_map.h"
#include "hardware/robot/simulated_twin.h"

namespace orcs::hardware {

class SimulatedShafts final : public ShaftModel {
 public:
  /// The map's joints, in its order, are the emulator's servos in id order: the map's ids must be ascending.
  SimulatedShafts(const std::string& environment_file, const JointMap& map,
                  const std::vector<std::string>& value_files);
  void Command(std::size_t index, double goal_deg, double torque) override;
  void Advance(double seconds) override;
  double Angle(std::size_t index) const override { return angles_.at(index); }
  double Speed(std::size_t index) const override { return speeds_.at(index); }

 private:
  SimulatedTwin world_;          // the simulation (the twin's machinery, fed by the bus instead)
  std::vector<double> goals_;    // per joint, degrees
  std::vector<double> torques_;  // per joint, 0…1
  std::vector<double> angles_;   // per joint, degrees, after the last Advance
  std::vector<double> speeds_;   // per joint, °/s over the last Advance
};

}  // namespace orcs::hardware
