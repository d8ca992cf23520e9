// The robot's simulated twin: the same commands the physical robot gets, fed to orcs's simulation of it period by
// period, at the same time (the original's "same controller on simulated and physical robots at the same time",
// its report §1). Its log sits beside the robot's, row for row, so that where the two part is plain to see and
// orcs-gap can take both.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hardware/robot/joint_map.h"

namespace orcs::scene {
class Simulation;
}

namespace orcs::hardware {

class SimulatedTwin {
 public:
  /// Builds the environment (its file; "" = the default world, the A-Series on the floor) with `value_files`
  /// applied (a fitted model, hidden effects) and finds the map's agent and joints in it. Throws InputError naming
  /// the environment when the agent or a joint is missing.
  SimulatedTwin(const std::string& environment_file, const JointMap& map,
                const std::vector<std::string>& value_files = {});
  ~SimulatedTwin();
  SimulatedTwin(const SimulatedTwin&) = delete;
  SimulatedTwin& operator=(const SimulatedTwin&) = delete;

  /// Puts the twin's joints where the robot's are (degrees, the map's order), at rest.
  void StartAt(const std::vector<double>& angles);
  /// Applies one period's commands (degrees and torque 0…1 per joint) and advances the simulation by `seconds`.
  /// Once the simulation has had trouble (unstable physics) it stops advancing; status() says why.
  void Advance(const std::vector<double>& goal, const std::vector<double>& torque, double seconds);
  /// The joints' simulated angles, degrees, in the map's order.
  std::vector<double> Angles() const;
  /// Poses the model kinematically — no physics step: reset, the joints at `angles`, their sensors reading them, their
  /// inputs `goal` (all degrees, the map's order). What orcs-robot --view records as the physical robot.
  void Pose(const std::vector<double>& angles, const std::vector<double>& goal);
  /// Writes the robot's measured angles (degrees, the map's order) into the twin's joint sensors, for a
  /// controller that reads them (hardware/robot/command_source.h).
  void SetJointSensors(const std::vector<double>& angles);
  /// The joints' inputs as a controller wrote them: DesiredAngle (degrees) and DesiredTorque, the map's order.
  void Inputs(std::vector<double>& goal, std::vector<double>& torque) const;
  scene::Simulation& simulation() { return *simulation_; }
  int agent_index() const { return agent_; }
  /// "" while the simulation runs; why it stopped otherwise.
  const std::string& status() const { return status_; }

 private:
  std::unique_ptr<scene::Simulation> simulation_;
  int agent_ = -1;                       // the map's agent in the simulation
  std::vector<std::string> joints_;       // the map's joints, in its order
  std::vector<std::string> joint_paths_;  // /Sim/<agent>/<joint>/ per joint of the map
  std::string status_;                   // why the twin stopped, "" while it runs
};

}  // namespace orcs::hardware
