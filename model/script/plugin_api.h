// The plug-in interface of orcs-worker (docs/extending.md, "Plug-ins"): what a compiled plug-in sees and provides.
// A plug-in is a shared library built against this one header — pure interfaces and standard types, nothing of orcs
// to link — that exports two C functions:
//
//   extern "C" int orcs_plugin_api_version() { return orcs::plugin::kApiVersion; }
//   extern "C" void orcs_plugin_register(orcs::plugin::Registrar& registrar) {
//     registrar.AddFitnessTerm("mean_height", [](const std::string& params_json) { return ...; });
//   }
//
// `orcs-worker --plugins DIR` loads every lib*.so of DIR; a library built for another kApiVersion is refused at the
// worker's start, naming both versions. A job names a component as "<plug-in>/<component>" (the plug-in's name is its
// file's, "libexample.so" → "example"): {"type": "plugin", "plugin": "example/mean_height", "params": {...}} as a
// fitness term or a controller (with "genome_length"). A worker without it refuses the job with PLUGIN_MISSING.
//
// Bump kApiVersion whenever anything in this file changes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace orcs::plugin {

inline constexpr int kApiVersion = 1;

/// What a plug-in reads of the running simulation, for the scenario's agent. Units as in the script API
/// (model/script/simulation_api.h): angles of the repository in degrees, physics in SI.
class SimulationView {
 public:
  virtual double time() const = 0;                      ///< simulated seconds since the reset
  virtual std::uint64_t seed() const = 0;               ///< the parameter set's seed (for a plug-in's own stream)
  virtual int motor_count() const = 0;                  ///< the agent's motors
  virtual std::string motor_name(int motor) const = 0;  ///< "Right/Knee", motor order
  virtual double joint_angle(int motor) const = 0;      ///< JointAngle, degrees
  virtual double joint_rate(int motor) const = 0;       ///< rad/s
  virtual double motor_torque(int motor) const = 0;     ///< N·m, in the last step
  virtual int body(const std::string& name) const = 0;  ///< a body handle of the agent ("Middle/Head"), −1 = none
  virtual void position(int body, double xyz[3]) const = 0;  ///< the body's origin, world frame, m (+y up)
  virtual bool contact(int body) const = 0;             ///< whether the body touched anything in the last step
  /// A numeric repository value (double, int or bool) at `path`; false when there is none.
  virtual bool value(const std::string& path, double& out) const = 0;

 protected:
  ~SimulationView() = default;
};

/// What a controller plug-in writes: the agent's motor inputs.
class MotorCommands {
 public:
  virtual void set_angle(int motor, double degrees) = 0;  ///< DesiredAngle
  virtual void set_torque(int motor, double torque) = 0;  ///< DesiredTorque, raw −1…1

 protected:
  ~MotorCommands() = default;
};

/// A fitness term: Start after the set's reset, Sample after every step, Value at the end.
class FitnessTerm {
 public:
  virtual ~FitnessTerm() = default;
  virtual void Start(const SimulationView& view) = 0;
  virtual void Sample(const SimulationView& view, double dt) = 0;
  virtual double Value() const = 0;
  /// True: the set may stop here (the robot fell).
  virtual bool Finished() const { return false; }
};

/// A controller: Reset after the set's reset, Update every control step at simulated time `time`.
class Controller {
 public:
  virtual ~Controller() = default;
  virtual void Reset(const SimulationView& view) = 0;
  virtual void Update(const SimulationView& view, MotorCommands& commands, double time) = 0;
};

/// What a motor model reads for its motor before each simulation step.
struct MotorInput {
  double angle = 0.0;           ///< joint angle, rad
  double rate = 0.0;            ///< joint rate, rad/s
  double torque = 0.0;          ///< torque the motor applied in the last step, N·m
  double desired_angle = 0.0;   ///< DesiredAngle, degrees (what the controller asks)
  double desired_torque = 0.0;  ///< DesiredTorque, raw −1…1
  double dt = 0.0;              ///< the step, s
};

/// What a motor model commands the joint for the coming step: the physics' angular motor drives the joint towards
/// `velocity` with at most `max_torque`, and a friction brake holds it with up to `friction_torque`.
struct MotorOutput {
  double velocity = 0.0;         ///< target joint rate, rad/s (finite)
  double max_torque = 0.0;       ///< N·m the motor may apply, ≥ 0
  double friction_torque = 0.0;  ///< N·m of joint friction, ≥ 0
};

/// A motor model, one per motor of the agent, in place of orcs's Dynamixel model (scenario "motor_model").
class MotorModel {
 public:
  virtual ~MotorModel() = default;
  /// After the set's reset; `angle` is the joint angle then, rad.
  virtual void Reset(double angle) = 0;
  virtual MotorOutput Update(const MotorInput& input) = 0;
};

/// Makes a term from the entry's "params" as JSON text; throws std::invalid_argument for bad params (the job is then
/// invalid input, with the message).
using FitnessTermFactory = std::function<std::unique_ptr<FitnessTerm>(const std::string& params_json)>;
/// Makes a controller from "params" and the job's genome ("genome_length" numbers).
using ControllerFactory =
    std::function<std::unique_ptr<Controller>(const std::string& params_json, const std::vector<double>& genome)>;

/// Makes motor `motor` ("Right/Knee")'s model from the scenario's "motor_model.params" as JSON text.
using MotorModelFactory =
    std::function<std::unique_ptr<MotorModel>(const std::string& params_json, const std::string& motor)>;

/// What orcs-worker hands a plug-in's orcs_plugin_register.
class Registrar {
 public:
  virtual void AddFitnessTerm(const std::string& component, FitnessTermFactory factory) = 0;
  virtual void AddController(const std::string& component, ControllerFactory factory) = 0;
  virtual void AddMotorModel(const std::string& component, MotorModelFactory factory) = 0;

 protected:
  ~Registrar() = default;
};

}  // namespace orcs::plugin
