// What a plug-in sees of a simulation (plugin::SimulationView) and writes (plugin::MotorCommands), over the same
// lookups the script API uses (SimulationApi).
#pragma once

#include "model/script/plugin_api.h"
#include "model/script/simulation_api.h"

namespace orcs::script {

class PluginView : public plugin::SimulationView, public plugin::MotorCommands {
 public:
  /// `inputs` as for SimulationApi: the repository when the plug-in may write motor inputs, else nullptr.
  PluginView(const scene::Simulation& simulation, int agent, VariableRepository* inputs)
      : api_(simulation, agent, inputs) {}

  double time() const override { return api_.simulation().time(); }
  std::uint64_t seed() const override { return api_.simulation().seed(); }
  int motor_count() const override { return static_cast<int>(api_.motor_names().size()); }
  std::string motor_name(int motor) const override { return api_.motor_names().at(motor); }
  double joint_angle(int motor) const override { return Motor(motor).angle->as_double(); }
  double joint_rate(int motor) const override { return api_.simulation().physics().joint_rate(Motor(motor).joint); }
  double motor_torque(int motor) const override {
    return api_.simulation().physics().joint_motor_torque(Motor(motor).joint);
  }
  int body(const std::string& name) const override { return api_.HandleOf(name); }
  void position(int body, double xyz[3]) const override;
  bool contact(int body) const override;
  bool value(const std::string& path, double& out) const override;

  void set_angle(int motor, double degrees) override;
  void set_torque(int motor, double torque) override;

 private:
  // Motor `motor` of the agent; throws std::out_of_range for another index (a plug-in's bug, reported as its error).
  const SimulationApi::Motor& Motor(int motor) const;
  SimulationApi api_;
};

}  // namespace orcs::script
