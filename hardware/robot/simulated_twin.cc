#include "hardware/robot/simulated_twin.h"

#include <algorithm>
#include <cmath>

#include "model/core/error.h"
#include "model/scene/simulation.h"
#include "model/scene/world_setup.h"

namespace orcs::hardware {

SimulatedTwin::SimulatedTwin(const std::string& environment_file, const JointMap& map,
                             const std::vector<std::string>& value_files)
    : simulation_(std::make_unique<scene::Simulation>()) {
  scene::SetUpWorld(*simulation_, environment_file, {}, value_files, UnknownPaths::kRefuse);
  simulation_->Reset(0);
  const std::string where = environment_file.empty() ? "the default world" : environment_file;
  agent_ = simulation_->FindAgent(map.agent);
  if (agent_ < 0) {
    throw InputError(map.source, 0, "the twin's environment (" + where + ") has no agent '" + map.agent +
                                        "' (give one with --twin-env, e.g. scenarios/environments/pendulum.xml)");
  }
  for (const JointMapping& joint : map.joints) {
    const std::string path = "/Sim/" + map.agent + "/" + joint.joint + "/";
    if (!simulation_->repository().Find(path + "DesiredAngle")) {
      throw InputError(map.source, 0, "joint '" + joint.joint + "' is not a motor of agent '" + map.agent + "' in " +
                                          where);
    }
    joint_paths_.push_back(path);
    joints_.push_back(joint.joint);
  }
}

SimulatedTwin::~SimulatedTwin() = default;

void SimulatedTwin::StartAt(const std::vector<double>& angles) {
  // Hinge angles are relative to the initial pose, as the robot's are to the map's zero; joints the map leaves
  // out stay at 0. A real servo reads a hair past the model's hinge stop now and then (its zero is not the model's
  // to the tick): the pose is clamped to the stops, which the model can hold.
  const std::vector<std::string>& motors = simulation_->agent(agent_).motor_names();
  const std::vector<aseries::MorphologyMotor>& stops = simulation_->model().morphology(agent_).motors;
  std::vector<double> all(motors.size(), 0.0);
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    for (std::size_t m = 0; m < motors.size(); ++m) {
      if (motors[m] == joints_[j]) all[m] = std::clamp(angles[j], stops[m].min_degrees, stops[m].max_degrees);
    }
  }
  simulation_->SetAgentJointAngles(agent_, all);
}

void SimulatedTwin::Pose(const std::vector<double>& angles, const std::vector<double>& goal) {
  simulation_->Reset(0);
  StartAt(angles);
  SetJointSensors(angles);
  for (std::size_t j = 0; j < joint_paths_.size(); ++j) {
    simulation_->repository().Get(joint_paths_[j] + "DesiredAngle").Set(goal[j]);
  }
}

void SimulatedTwin::Advance(const std::vector<double>& goal, const std::vector<double>& torque, double seconds) {
  if (!status_.empty()) return;
  VariableRepository& values = simulation_->repository();
  for (std::size_t j = 0; j < joint_paths_.size(); ++j) {
    values.Get(joint_paths_[j] + "DesiredAngle").Set(goal[j]);
    values.Get(joint_paths_[j] + "DesiredTorque").Set(torque[j]);
  }
  const double end = simulation_->time() + seconds;
  while (simulation_->time() + simulation_->StepDuration() / 2 < end) {
    if (simulation_->Step() != scene::SimulationStatus::kOk) {
      status_ = "the twin's simulation stopped at " + std::to_string(simulation_->time()) + " s: " +
                simulation_->message();
      return;
    }
  }
}

void SimulatedTwin::SetJointSensors(const std::vector<double>& angles) {
  for (std::size_t j = 0; j < joint_paths_.size(); ++j) {
    simulation_->repository().Get(joint_paths_[j] + "JointAngle").Set(angles[j]);
  }
}

void SimulatedTwin::Inputs(std::vector<double>& goal, std::vector<double>& torque) const {
  for (std::size_t j = 0; j < joint_paths_.size(); ++j) {
    goal[j] = simulation_->repository().Get(joint_paths_[j] + "DesiredAngle").as_double();
    torque[j] = simulation_->repository().Get(joint_paths_[j] + "DesiredTorque").as_double();
  }
}

std::vector<double> SimulatedTwin::Angles() const {
  std::vector<double> angles;
  for (const std::string& path : joint_paths_) {
    angles.push_back(simulation_->repository().Get(path + "JointAngle").as_double());
  }
  return angles;
}

}  // namespace orcs::hardware
