// One A-Series robot in one simulation: its interface values in the repository, its motors' and sensors'
// memory, and the two stages it adds to the step (motors before the physics, sensors after it, spec §8).
//
// Values (spec §4d), for agent A and motor M (e.g. "Right/Knee"), board B (e.g. "ABFR"):
//   /Sim/A/M/DesiredAngle   double, degrees, clamped to ±150 (input)
//   /Sim/A/M/DesiredTorque  double, fraction of the maximum torque, −1…1; ≤ 0 gives no torque (input)
//   /Sim/A/M/JointAngle     double, degrees, with sensor noise (output)
//   /Sim/A/M/CurrentVelocity double, rad/s, the velocity the motor controller commands
//   /Sim/A/M/MotorTorque    double, N·m, the torque the motor applied in the last step (output, for analysis)
//   /Sim/A/M/MinAngle, MaxAngle  double, degrees, the hinge stops (structure values, morphology_values.h)
//   /Sim/A/M/AngularMotor/...    the motor's own copies of the global motor parameters (per_motor_parameters.h)
//   /Sim/A/B/AccelAxis1, AccelAxis2  double, m/s² (output)
// and the global motor and sensor parameters /AngularMotor/..., /AccelSensor/... (docs/model.md), and the motor
// effects /Effects/... (motor_effects.h, docs/gap.md), all off by default.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "model/script/plugin_api.h"
#include "model/aseries/accelerometer.h"
#include "model/aseries/angle_sensor.h"
#include "model/aseries/aseries_builder.h"
#include "model/aseries/aseries_morphology.h"
#include "model/aseries/dynamixel_motor.h"
#include "model/aseries/motor_effects.h"
#include "model/core/random_stream.h"
#include "model/core/variable_repository.h"
#include "model/physics/gravity_load.h"
#include "model/physics/physics_world.h"

namespace orcs::aseries {

class ASeriesAgent {
 public:
  /// Registers the agent's values (and the global parameters, once per repository) and binds them.
  /// `index` numbers the agents of a world (0, 1, ...) and selects this agent's random streams.
  ASeriesAgent(const ASeriesMorphology& morphology, ASeriesLayout layout, int index, VariableRepository& values);

  /// Registers the parameters every agent shares (/AngularMotor/..., the sensors' and the motor effects') with
  /// their defaults, where they are not yet: before the world is built, so that initial value files (-ival) can
  /// set them as in the original.
  static void AddSharedParameters(VariableRepository& values);

  /// AddSharedParameters, then agent `agent`'s per-motor copies of the motor and angle-sensor parameters
  /// (per_motor_parameters.h), so that initial value files can set one motor's parameters before the build too.
  static void AddAgentParameters(VariableRepository& values, const std::string& agent,
                                 const ASeriesMorphology& morphology);

  const std::string& name() const { return layout_.agent_name; }
  const ASeriesLayout& layout() const { return layout_; }
  int motor_count() const { return static_cast<int>(motors_.size()); }
  /// Motor names in motor (= input) order, without the agent, e.g. "Right/Knee".
  const std::vector<std::string>& motor_names() const { return motor_names_; }
  int board_count() const { return static_cast<int>(boards_.size()); }

  /// Back to the initial state after the world has been reset; noise streams restart from `seed`.
  void Reset(const physics::PhysicsWorld& world, std::uint64_t seed);

  /// After the world was compiled anew from changed structure values (Simulation::Reset, before this agent's
  /// Reset): the boards' placement and the hinges' axes as `morphology` and `layout` have them now. The bodies,
  /// joints and boards are the same ones (values change numbers only), so every index stays valid.
  void UpdateGeometry(const ASeriesMorphology& morphology, const ASeriesLayout& layout);

  /// Puts a plug-in's motor model in place of the Dynamixel model, one per motor in motor order (scenario
  /// "motor_model", docs/extending.md); empty = the Dynamixel model again. In force from the next Reset.
  void SetPluginMotors(std::vector<std::unique_ptr<plugin::MotorModel>> models);

  /// Motor stage: every motor's controller reads its joint angle and desired values and sets the joint's motor
  /// velocity, torque limit and friction (spec §6b), in motor order.
  void MotorStage(physics::PhysicsWorld& world, double dt);

  /// Sensor stage, after the physics step: angle sensors in motor order, then accelerometers in board order.
  void SensorStage(const physics::PhysicsWorld& world, double dt);

 private:
  struct Motor {
    int joint = -1;                   // physics joint index
    Value* desired_angle = nullptr;   // degrees
    Value* desired_torque = nullptr;  // −1…1
    Value* joint_angle = nullptr;     // degrees
    Value* current_velocity = nullptr;  // rad/s
    Value* motor_torque = nullptr;      // N·m
    std::string parameter_prefix;       // "/Sim/<agent>/<motor>": where its own parameter copies are
    DynamixelParameters parameters;     // this motor's, from its copies
    AngleSensorParameters sensor;       // this motor's angle sensor's, from its copies
    ServoParameters servo;              // this motor's physical servo model's, from its copies
    DynamixelState state;
    MotorEffectState effect_state;
    int distal_body = -1;  // physics body on the far side from the root: it carries the rotor inertia
    Eigen::Vector3d axis_in_body = Eigen::Vector3d::UnitX();  // the hinge axis in that body's frame
    std::vector<int> load_bodies;  // physics bodies on the far side from the root: the load the motor holds
    std::optional<physics::GravityLoad> gravity_load;  // their gravity torque about the hinge (set at Reset)
    std::unique_ptr<plugin::MotorModel> plugin;  // a plug-in's model in place of the Dynamixel one; null = none
  };
  struct Board {
    int host_body = -1;  // physics body index
    std::string parameter_prefix;  // "/Sim/<agent>/<board>": where its own parameter copies are
    AccelerometerParameters parameters;  // this board's, from its copies (gravity: the simulation's)
    AccelerometerBoard board;
    Value* axis1 = nullptr;  // m/s²
    Value* axis2 = nullptr;  // m/s²
    AccelerometerState state;
  };

  void ReadParameters();
  void WatchCopy(VariableRepository& values, const std::string& prefix, std::string_view path);
  void FindDistalBodies(const ASeriesMorphology& morphology);
  void MoveMotor(physics::PhysicsWorld& world, Motor& motor, double dt);
  void AddRotorInertia(physics::PhysicsWorld& world);

  ASeriesLayout layout_;
  int index_ = 0;
  VariableRepository& values_;
  std::vector<Motor> motors_;
  std::vector<std::string> motor_names_;
  std::vector<Board> boards_;
  AccelerometerParameters gravity_;  // only its gravity: /Simulation/Gravitation
  MotorEffects effects_;
  bool servo_enabled_ = false;       // /Servo/Enabled: the physical servo model runs for every motor
  bool rotor_inertia_added_ = false;  // since the last Reset (the world's Reset takes it away)
  bool parameters_changed_ = true;  // set by observers of the global parameter values
  std::optional<RandomStream> motor_noise_;
  std::optional<RandomStream> angle_noise_;
  std::optional<RandomStream> accel_noise_;
};

}  // namespace orcs::aseries
