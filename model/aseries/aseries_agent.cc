#include "model/aseries/aseries_agent.h"

#include <algorithm>
#include <deque>
#include <map>
#include <set>

#include "base/demand.h"
#include "model/aseries/per_motor_parameters.h"
#include "model/aseries/value_range.h"
#include "model/core/rotation.h"

namespace orcs::aseries {
namespace {

template <typename Parameters, std::size_t N>
void WatchParameters(VariableRepository& values, const std::array<ParameterField<Parameters>, N>& table,
                     bool& changed) {
  AddParameters(values, table);
  for (const auto& field : table) values.Get(field.path).AddObserver([&changed](const Value&) { changed = true; });
}

}  // namespace

void ASeriesAgent::WatchCopy(VariableRepository& values, const std::string& prefix, std::string_view path) {
  values.Get(prefix + std::string(path)).AddObserver([this](const Value&) { parameters_changed_ = true; });
}

void ASeriesAgent::AddSharedParameters(VariableRepository& values) {
  AddParameters(values, kDynamixelParameterTable);
  AddParameters(values, kAngleSensorParameterTable);
  AddParameters(values, kAccelerometerParameterTable);
  AddParameters(values, kAccelerometerGravityTable);
  AddParameters(values, kMotorEffectsTable);
  AddParameters(values, kServoParameterTable);
}

void ASeriesAgent::AddAgentParameters(VariableRepository& values, const std::string& agent,
                                      const ASeriesMorphology& morphology) {
  AddSharedParameters(values);
  std::vector<std::string> motors, boards;
  for (const MorphologyMotor& motor : morphology.motors) motors.push_back(motor.name);
  for (const MorphologyBoard& board : morphology.boards) boards.push_back(board.name);
  AddPerMotorParameters(values, agent, motors, boards);
}

ASeriesAgent::ASeriesAgent(const ASeriesMorphology& morphology, ASeriesLayout layout, int index,
                           VariableRepository& values)
    : layout_(std::move(layout)), index_(index), values_(values) {
  WatchParameters(values, kDynamixelParameterTable, parameters_changed_);
  WatchParameters(values, kAngleSensorParameterTable, parameters_changed_);
  WatchParameters(values, kAccelerometerGravityTable, parameters_changed_);
  WatchParameters(values, kMotorEffectsTable, parameters_changed_);
  WatchParameters(values, kServoParameterTable, parameters_changed_);
  AddAgentParameters(values, layout_.agent_name, morphology);
  const std::string prefix = "/Sim/" + layout_.agent_name + "/";
  motors_.resize(morphology.motors.size());
  for (size_t m = 0; m < motors_.size(); ++m) {
    const MorphologyMotor& spec = morphology.motors[m];
    const std::string path = prefix + spec.name + "/";
    Motor& motor = motors_[m];
    motor_names_.push_back(spec.name);
    motor.joint = layout_.motors[m];
    motor.desired_angle = &values.Add(path + "DesiredAngle", 0.0);
    motor.desired_torque = &values.Add(path + "DesiredTorque", kDefaultDesiredTorqueRaw);
    motor.joint_angle = &values.Add(path + "JointAngle", 0.0);
    motor.current_velocity = &values.Add(path + "CurrentVelocity", 0.0);
    motor.motor_torque = &values.Add(path + "MotorTorque", 0.0);
    motor.parameter_prefix = PerMotorPrefix(layout_.agent_name, spec.name);
    for (const std::string_view copied : PerMotorPaths()) WatchCopy(values, motor.parameter_prefix, copied);
    // The angle sensor's range, published as the original did (spec §4d); informative: the sensor model reads
    // its own parameters (kAngleSensorParameterTable).
    values.Add(path + "MinSensorAngle", -150.0);
    values.Add(path + "MaxSensorAngle", 150.0);
  }
  boards_.resize(layout_.boards.size());
  for (size_t b = 0; b < boards_.size(); ++b) {
    const ASeriesBoardLayout& spec = layout_.boards[b];
    Board& board = boards_[b];
    board.host_body = spec.host_body;
    board.parameter_prefix = PerMotorPrefix(layout_.agent_name, spec.name);
    for (const std::string_view copied : PerBoardPaths()) WatchCopy(values, board.parameter_prefix, copied);
    board.board = MakeAccelerometerBoard(spec.local_position, spec.local_rotation);
    board.axis1 = &values.Add(prefix + spec.name + "/AccelAxis1", 0.0);
    board.axis2 = &values.Add(prefix + spec.name + "/AccelAxis2", 0.0);
  }
  FindDistalBodies(morphology);
}

// Breadth-first from the root body over the motors and fixed joints: of a motor's two bodies the one found later
// is on the far side. A motor holding a body to the static world ("" body 2, the rigs) turns that body.
void ASeriesAgent::FindDistalBodies(const ASeriesMorphology& morphology) {
  std::multimap<std::string, std::string> links;
  const auto link = [&links](const std::string& a, const std::string& b) {
    links.emplace(a, b);
    links.emplace(b, a);
  };
  for (const MorphologyMotor& motor : morphology.motors) link(motor.first_body, motor.second_body);
  for (const MorphologyFixedJoint& joint : morphology.fixed_joints) link(joint.first_body, joint.second_body);
  std::map<std::string, int> depth{{"", -1}, {morphology.root_body, 0}};
  std::deque<std::string> queue{morphology.root_body};
  while (!queue.empty()) {
    const std::string body = queue.front();
    queue.pop_front();
    const auto [first, last] = links.equal_range(body);
    for (auto it = first; it != last; ++it) {
      if (depth.emplace(it->second, depth[body] + 1).second) queue.push_back(it->second);
    }
  }
  for (size_t m = 0; m < motors_.size(); ++m) {
    const MorphologyMotor& spec = morphology.motors[m];
    const bool first_is_distal = spec.second_body.empty() || depth[spec.first_body] > depth[spec.second_body];
    const std::string& distal = first_is_distal ? spec.first_body : spec.second_body;
    motors_[m].distal_body = layout_.bodies[static_cast<size_t>(morphology.FindBody(distal))];
    // The load: the distal body and every body beyond it (deeper from the root, reached through it).
    std::deque<std::string> beyond{distal};
    std::set<std::string> load{distal};
    while (!beyond.empty()) {
      const std::string body = beyond.front();
      beyond.pop_front();
      const auto [first, last] = links.equal_range(body);
      for (auto it = first; it != last; ++it) {
        if (depth[it->second] > depth[body] && load.insert(it->second).second) beyond.push_back(it->second);
      }
    }
    for (const std::string& body : load) {
      motors_[m].load_bodies.push_back(layout_.bodies[static_cast<size_t>(morphology.FindBody(body))]);
    }
    // Morphology bodies are axis-aligned in the initial pose, so the world axis is also the body-frame axis.
    motors_[m].axis_in_body = (spec.axis_point2 - spec.axis_point1).normalized();
  }
}

void ASeriesAgent::UpdateGeometry(const ASeriesMorphology& morphology, const ASeriesLayout& layout) {
  layout_ = layout;
  for (size_t b = 0; b < boards_.size(); ++b) {
    boards_[b].board = MakeAccelerometerBoard(layout_.boards[b].local_position, layout_.boards[b].local_rotation);
  }
  for (size_t m = 0; m < motors_.size(); ++m) {
    const MorphologyMotor& spec = morphology.motors[m];
    motors_[m].axis_in_body = (spec.axis_point2 - spec.axis_point1).normalized();  // as FindDistalBodies
  }
}

void ASeriesAgent::ReadParameters() {
  aseries::ReadParameters(values_, kMotorEffectsTable, effects_);
  servo_enabled_ = values_.Get(kServoEnabledPath).as_bool();  // one switch for all: which model runs
  for (Motor& motor : motors_) {
    aseries::ReadParameters(values_, kDynamixelParameterTable, motor.parameters, motor.parameter_prefix);
    aseries::ReadParameters(values_, kAngleSensorParameterTable, motor.sensor, motor.parameter_prefix);
    aseries::ReadParameters(values_, kServoParameterTable, motor.servo, motor.parameter_prefix, kServoEnabledPath);
    CheckEffectsFitServo(motor.servo, effects_);
  }
  aseries::ReadParameters(values_, kAccelerometerGravityTable, gravity_);
  for (Board& board : boards_) {
    aseries::ReadParameters(values_, kAccelerometerParameterTable, board.parameters, board.parameter_prefix);
    board.parameters.gravity = gravity_.gravity;
  }
  parameters_changed_ = false;
}


void ASeriesAgent::Reset(const physics::PhysicsWorld& world, std::uint64_t seed) {
  const auto stream_index = static_cast<std::uint64_t>(index_);
  motor_noise_.emplace(seed, "aseries/motor-noise", stream_index);
  angle_noise_.emplace(seed, "aseries/angle-sensor-noise", stream_index);
  accel_noise_.emplace(seed, "aseries/accelerometer-noise", stream_index);
  for (Motor& motor : motors_) {
    aseries::Reset(motor.state, world.joint_angle(motor.joint));
    ResetEffects(motor.effect_state, world.joint_angle(motor.joint));
    motor.motor_torque->Set(0.0);
    motor.joint_angle->Set(RadiansToDegrees(world.joint_angle(motor.joint)));
    motor.current_velocity->Set(0.0);
    motor.gravity_load.emplace(world.model(), motor.joint, motor.load_bodies);
    if (motor.plugin) motor.plugin->Reset(world.joint_angle(motor.joint));
  }
  for (Board& board : boards_) {
    const physics::BodyState host = world.body_state(board.host_body);
    aseries::Reset(board.state, board.board, host.position, host.orientation);
  }
  rotor_inertia_added_ = false;
}

void ASeriesAgent::MotorStage(physics::PhysicsWorld& world, double dt) {
  if (parameters_changed_) ReadParameters();
  if ((effects_.rotor_inertia || servo_enabled_) && !rotor_inertia_added_) AddRotorInertia(world);
  for (Motor& motor : motors_) MoveMotor(world, motor, dt);
}

void ASeriesAgent::SetPluginMotors(std::vector<std::unique_ptr<plugin::MotorModel>> models) {
  ORCS_DEMAND_MSG(models.empty() || models.size() == motors_.size(), "SetPluginMotors: one model per motor");
  for (std::size_t m = 0; m < motors_.size(); ++m) motors_[m].plugin = models.empty() ? nullptr : std::move(models[m]);
}

namespace {

// A plug-in's command, held to what the physics accepts: a non-finite or negative number is the plug-in's bug.
DynamixelCommand PluginCommand(plugin::MotorModel& model, const plugin::MotorInput& input, const std::string& motor) {
  const plugin::MotorOutput out = model.Update(input);
  if (!std::isfinite(out.velocity) || !(out.max_torque >= 0.0) || !std::isfinite(out.max_torque) ||
      !(out.friction_torque >= 0.0) || !std::isfinite(out.friction_torque)) {
    throw std::runtime_error("plug-in motor model of " + motor + ": a command needs a finite velocity and finite "
                             "torques ≥ 0");
  }
  return {out.velocity, out.max_torque, out.friction_torque};
}

}  // namespace

void ASeriesAgent::MoveMotor(physics::PhysicsWorld& world, Motor& motor, double dt) {
  const double angle = world.joint_angle(motor.joint);
  const double desired_angle = motor.desired_angle->as_double();
  const double desired_torque = motor.desired_torque->as_double();
  DynamixelCommand command;
  if (motor.plugin) {
    const plugin::MotorInput input{angle, world.joint_rate(motor.joint), world.joint_motor_torque(motor.joint),
                                   desired_angle, desired_torque, dt};
    command = PluginCommand(*motor.plugin, input, motor.parameter_prefix);
  } else if (effects_.any() || servo_enabled_) {  // the original's bits stay untouched while every effect is off
    // Gravity's torque on the load only where an effect reads it: it costs a pass over the load's bodies.
    const double gravity_torque =
        effects_.gravity_load_friction
            ? motor.gravity_load->Torque(world, Eigen::Vector3d(0.0, -gravity_.gravity, 0.0))
            : 0.0;
    const JointReading reading{angle, world.joint_rate(motor.joint), world.joint_motor_torque(motor.joint),
                               gravity_torque};
    const EffectCommand with_effects = UpdateWithEffects(motor.parameters, motor.servo, effects_, motor.state,
                                                         motor.effect_state, reading, desired_angle, desired_torque,
                                                         dt, &*motor_noise_);
    world.SetJointMotorCompliance(motor.joint, with_effects.compliance);
    command = with_effects.motor;
  } else {
    command = Update(motor.parameters, motor.state, angle, desired_angle, desired_torque, dt, &*motor_noise_);
  }
  world.SetJointMotor(motor.joint, command.velocity, command.max_torque);
  world.SetJointFriction(motor.joint, command.friction_torque);
  motor.current_velocity->Set(command.velocity);
}

// The effect's rotor inertia and the servo mode's armature: both are the rotor's, reflected through the gearbox.
void ASeriesAgent::AddRotorInertia(physics::PhysicsWorld& world) {
  for (const Motor& motor : motors_) {
    const double inertia = (effects_.rotor_inertia ? std::max(effects_.inertia, 0.0) : 0.0) +
                           (servo_enabled_ ? std::max(motor.servo.armature, 0.0) : 0.0);
    world.AddBodyInertia(motor.distal_body, motor.axis_in_body, inertia);
  }
  rotor_inertia_added_ = true;
}

void ASeriesAgent::SensorStage(const physics::PhysicsWorld& world, double dt) {
  for (Motor& motor : motors_) {
    motor.joint_angle->Set(MeasureJointAngle(world.joint_angle(motor.joint), motor.sensor, &*angle_noise_));
    motor.motor_torque->Set(world.joint_motor_torque(motor.joint));
  }
  for (Board& board : boards_) {
    const physics::BodyState host = world.body_state(board.host_body);
    const std::array<double, 2> reading = Measure(board.parameters, board.board, board.state, host.position,
                                                  host.orientation, dt, &*accel_noise_);
    board.axis1->Set(reading[0]);
    board.axis2->Set(reading[1]);
  }
}

}  // namespace orcs::aseries
