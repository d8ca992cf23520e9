#include "model/aseries/aseries_agent.h"

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

ASeriesAgent::ASeriesAgent(const ASeriesMorphology& morphology, ASeriesLayout layout, int index,
                           VariableRepository& values)
    : layout_(std::move(layout)), index_(index), values_(values) {
  WatchParameters(values, kDynamixelParameterTable, parameters_changed_);
  WatchParameters(values, kAngleSensorParameterTable, parameters_changed_);
  WatchParameters(values, kAccelerometerParameterTable, parameters_changed_);
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
    values.Add(path + "MinAngle", spec.min_degrees);
    values.Add(path + "MaxAngle", spec.max_degrees);
  }
  boards_.resize(layout_.boards.size());
  for (size_t b = 0; b < boards_.size(); ++b) {
    const ASeriesBoardLayout& spec = layout_.boards[b];
    Board& board = boards_[b];
    board.host_body = spec.host_body;
    board.board = MakeAccelerometerBoard(spec.local_position, spec.local_rotation);
    board.axis1 = &values.Add(prefix + spec.name + "/AccelAxis1", 0.0);
    board.axis2 = &values.Add(prefix + spec.name + "/AccelAxis2", 0.0);
  }
}

void ASeriesAgent::ReadParameters() {
  aseries::ReadParameters(values_, kDynamixelParameterTable, motor_parameters_);
  aseries::ReadParameters(values_, kAngleSensorParameterTable, angle_parameters_);
  aseries::ReadParameters(values_, kAccelerometerParameterTable, accel_parameters_);
  parameters_changed_ = false;
}

void ASeriesAgent::Reset(const physics::PhysicsWorld& world, std::uint64_t seed) {
  const auto stream_index = static_cast<std::uint64_t>(index_);
  motor_noise_.emplace(seed, "aseries/motor-noise", stream_index);
  angle_noise_.emplace(seed, "aseries/angle-sensor-noise", stream_index);
  accel_noise_.emplace(seed, "aseries/accelerometer-noise", stream_index);
  for (Motor& motor : motors_) {
    aseries::Reset(motor.state, world.joint_angle(motor.joint));
    motor.joint_angle->Set(RadiansToDegrees(world.joint_angle(motor.joint)));
    motor.current_velocity->Set(0.0);
  }
  for (Board& board : boards_) {
    const physics::BodyState host = world.body_state(board.host_body);
    aseries::Reset(board.state, board.board, host.position, host.orientation);
  }
}

void ASeriesAgent::MotorStage(physics::PhysicsWorld& world, double dt) {
  if (parameters_changed_) ReadParameters();
  for (Motor& motor : motors_) {
    const DynamixelCommand command =
        Update(motor_parameters_, motor.state, world.joint_angle(motor.joint), motor.desired_angle->as_double(),
               motor.desired_torque->as_double(), dt, &*motor_noise_);
    world.SetJointMotor(motor.joint, command.velocity, command.max_torque);
    world.SetJointFriction(motor.joint, command.friction_torque);
    motor.current_velocity->Set(command.velocity);
  }
}

void ASeriesAgent::SensorStage(const physics::PhysicsWorld& world, double dt) {
  for (Motor& motor : motors_) {
    motor.joint_angle->Set(MeasureJointAngle(world.joint_angle(motor.joint), angle_parameters_, &*angle_noise_));
  }
  for (Board& board : boards_) {
    const physics::BodyState host = world.body_state(board.host_body);
    const std::array<double, 2> reading = Measure(accel_parameters_, board.board, board.state, host.position,
                                                  host.orientation, dt, &*accel_noise_);
    board.axis1->Set(reading[0]);
    board.axis2->Set(reading[1]);
  }
}

}  // namespace orcs::aseries
