// The driven pendulum rig (scenarios/environments/pendulum.xml: one motor turning a pole that hangs straight
// down at angle 0) as a test fixture: values set through the repository as a -val file would, noise off, and the
// pole's inertia and gravity torque read from the rig's own description. Shared by the motor-model tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "model/physics/physics_model.h"
#include "model/scene/environment_reader.h"
#include "model/scene/simulation.h"

namespace orcs::aseries {

inline std::string SourcePath(const std::string& relative) {
  return std::string(ORCS_SOURCE_DIR) + "/" + relative;
}

using Values = std::vector<std::pair<std::string, std::string>>;

// The driven pendulum rig on `engine`, noise off, with `values` assigned through the repository after the build
// (as a -val file would), then reset. At angle 0 the pole hangs straight down; positive angles lift it towards +x.
class PendulumRig {
 public:
  explicit PendulumRig(const Values& values, const std::string& engine) {
    simulation_.LoadEnvironment(scene::EnvironmentReader::ReadFile(SourcePath("scenarios/environments/pendulum.xml")));
    simulation_.Build();
    Set("/Simulation/Engine", engine);
    Set("/AngularMotor/IncludeNoise", "false");
    for (const auto& [path, value] : values) Set(path, value);
    simulation_.Reset(0);
    joint_ = simulation_.agent(0).layout().motors[0];
  }

  void Set(const std::string& path, const std::string& value) { simulation_.repository().Set(path, value); }
  void Command(double degrees, double torque_raw = 1.0) {
    simulation_.repository().Get("/Sim/Pendulum/Motor/DesiredAngle").Set(degrees);
    simulation_.repository().Get("/Sim/Pendulum/Motor/DesiredTorque").Set(torque_raw);
  }
  // Poses the pole at rest at `degrees`, right after the construction.
  void Pose(double degrees) { simulation_.SetAgentJointAngles(0, {degrees}); }
  bool Step() { return simulation_.Step() == scene::SimulationStatus::kOk; }
  // `steps` steps; false (and a test failure) at the first that is not ok.
  bool Run(int steps) {
    for (int i = 0; i < steps; ++i) {
      if (!Step()) {
        ADD_FAILURE() << simulation_.message();
        return false;
      }
    }
    return true;
  }

  double Degrees() const { return simulation_.physics().joint_angle(joint_) * 180.0 / 3.14159265358979323846; }
  double Rate() const { return simulation_.physics().joint_rate(joint_); }
  scene::Simulation& simulation() { return simulation_; }
  const physics::PhysicsModel& physics_model() const { return *simulation_.model().physics(); }
  int joint() const { return joint_; }

  // The pole's moment of inertia about the hinge, kg·m², from the rig's own description: a uniform box (the main
  // geom's size, the body's mass) about its centre, plus m·d² for the centre's distance from the axis.
  double Inertia() const {
    const physics::PhysicsModel& model = physics_model();
    const physics::JointDescription& hinge = model.joint(joint_);
    const physics::BodyDescription& pole = model.body(model.joint_body1(joint_));
    const Eigen::Vector3d axis = hinge.axis.normalized();
    const Eigen::Vector3d size = pole.geoms.at(0).size;  // the rig's axis is +z: the box turns in its x-y plane
    EXPECT_NEAR(std::abs(axis.z()), 1.0, 1e-12);
    const Eigen::Vector3d arm = pole.position - hinge.anchor;
    const double distance = (arm - arm.dot(axis) * axis).norm();
    return pole.mass * (size.x() * size.x() + size.y() * size.y()) / 12.0 + pole.mass * distance * distance;
  }
  // m·g·d, N·m: gravity's torque with the pole horizontal.
  double GravityTorque() const {
    const physics::PhysicsModel& model = physics_model();
    const physics::JointDescription& hinge = model.joint(joint_);
    const physics::BodyDescription& pole = model.body(model.joint_body1(joint_));
    constexpr double kG = 9.81;  // m/s²
    return pole.mass * kG * (pole.position - hinge.anchor).norm();
  }

 private:
  scene::Simulation simulation_;
  int joint_ = -1;
};

}  // namespace orcs::aseries
