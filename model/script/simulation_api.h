// What a script sees of its simulation: the `orcs` table (docs/extending.md, "The orcs table"). Every function reads
// the running simulation of one agent — the repository's values, the physics' bodies, joints and contacts, time —
// and a controller's script may also write that agent's motor inputs. Units are orcs's own: the repository's values
// as they are (angles in degrees), the physics' in SI (m, m/s, rad/s, N·m).
//
//   orcs.time()                      simulated seconds since the reset
//   orcs.value(path)                 any repository value: a number, boolean or string; a vector as x, y, z;
//                                    a quaternion as w, x, y, z; a colour as r, g, b, a
//   orcs.motors()                    the agent's motor names, in motor order (a table)
//   orcs.motor(name)                 a handle of the motor (its index in orcs.motors()): faster than a name in a loop
//   orcs.angle(motor)                the motor's JointAngle, degrees (a motor: a handle or a name)
//   orcs.joint_rate(motor)           the hinge's rate, rad/s (the physics' own: what the energy term uses)
//   orcs.motor_torque(motor)         the torque the motor applied in the last step, N·m
//   orcs.body(name)                  a handle of the agent's body "Middle/Head" (faster than a name in a loop)
//   orcs.position(body)              its origin, world frame, m (x, y, z; +y up)
//   orcs.velocity(body)              its linear velocity, m/s (x, y, z)
//   orcs.orientation(body)           its orientation quaternion (w, x, y, z)
//   orcs.tilt(body)                  the angle between its +y axis and the world's +y, degrees
//   orcs.contact(body)               whether it touched anything in the last step (excluded pairs do not count)
//   orcs.accel(board)                the accelerometer board's two axes, m/s² ("ABFR")
//   orcs.random()                    uniform in [0, 1) from the parameter set's own stream (as math.random())
//   orcs.set_angle(motor, degrees)   controllers only: the motor's DesiredAngle
//   orcs.set_torque(motor, torque)   controllers only: the motor's DesiredTorque (raw, −1…1)
#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "model/core/variable_repository.h"
#include "model/scene/simulation.h"
#include "model/script/script_sandbox.h"

namespace orcs::script {

class SimulationApi {
 public:
  /// The API for agent `agent` of the built `simulation`. `inputs`: the simulation's repository when the script
  /// may write the agent's motor inputs (a controller), nullptr when it only reads (a fitness term).
  SimulationApi(const scene::Simulation& simulation, int agent, VariableRepository* inputs);
  SimulationApi(const SimulationApi&) = delete;
  SimulationApi& operator=(const SimulationApi&) = delete;

  /// Adds the `orcs` table to the script's globals. The API must outlive the sandbox's calls.
  void Open(ScriptSandbox& sandbox);

  // What the table's functions use (public for them; a failed lookup is −1 or nullptr).
  struct Motor {
    int joint = -1;                 ///< physics joint index
    const Value* angle = nullptr;   ///< JointAngle, degrees
    Value* desired_angle = nullptr;   ///< DesiredAngle, degrees (nullptr when read-only)
    Value* desired_torque = nullptr;  ///< DesiredTorque, raw (nullptr when read-only)
  };
  const scene::Simulation& simulation() const { return simulation_; }
  const std::string& agent_name() const { return agent_name_; }
  bool writable() const { return inputs_ != nullptr; }
  const std::vector<std::string>& motor_names() const { return motor_names_; }
  const Motor* FindMotor(std::string_view name) const;
  /// Motor `handle` (orcs.motor's result: its index in motor order, from 1), nullptr when out of range.
  const Motor* MotorOfHandle(long long handle) const;
  /// Physics body index of the agent's body `name`, −1 when it has none.
  int FindBody(std::string_view name) const;
  /// Physics body index of handle `handle` (orcs.body's result), −1 when out of range.
  int BodyOfHandle(long long handle) const;
  /// The board's two axes, nullptr when the agent has no such board.
  const std::pair<const Value*, const Value*>* FindBoard(std::string_view name) const;
  /// Handle of the agent's body `name` for orcs.body, −1 when it has none.
  int HandleOf(std::string_view name) const;

 private:
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view text) const { return std::hash<std::string_view>{}(text); }
  };
  template <typename T>
  using ByName = std::unordered_map<std::string, T, NameHash, std::equal_to<>>;

  const scene::Simulation& simulation_;
  VariableRepository* inputs_;
  std::string agent_name_;
  std::vector<std::string> motor_names_;
  ByName<Motor> motors_;
  std::vector<const Motor*> motor_order_;  ///< motors_ in motor order: handle − 1 → motor
  ByName<int> body_handles_;      ///< morphology body name → handle (its morphology index)
  std::vector<int> handle_bodies_;  ///< handle → physics body index
  ByName<std::pair<const Value*, const Value*>> boards_;
};

}  // namespace orcs::script
