// Small worlds for the physics backends' tests (physics_world_test.cc runs them on every engine; ode/ and mujoco/
// hold what is engine-specific): a floor, spheres and boxes, a hinged pendulum, a motorised chain, a ball over a
// shelf, and stepping helpers.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "model/physics/physics_model.h"
#include "model/physics/physics_world.h"

namespace orcs::physics::test_worlds {

constexpr double kDt = 0.01;
constexpr double kG = 9.81;
constexpr double kPi = std::numbers::pi;

inline GeomDescription MakeGeom(Shape shape, const Eigen::Vector3d& size, const std::string& material) {
  GeomDescription geom;
  geom.shape = shape;
  geom.size = size;
  geom.material = material;
  return geom;
}

inline BodyDescription Floor(const std::string& material = "PVC") {
  BodyDescription floor;
  floor.name = "Floor";
  floor.dynamic = false;
  floor.geoms.push_back(MakeGeom(Shape::kPlane, Eigen::Vector3d::Zero(), material));
  return floor;
}

inline BodyDescription Sphere(const std::string& name, double radius, double mass, const std::string& material,
                       const Eigen::Vector3d& position) {
  BodyDescription body;
  body.name = name;
  body.mass = mass;
  body.position = position;
  body.geoms.push_back(MakeGeom(Shape::kSphere, {radius, 0, 0}, material));
  return body;
}

inline BodyDescription Box(const std::string& name, const Eigen::Vector3d& size, double mass, const std::string& material,
                    const Eigen::Vector3d& position) {
  BodyDescription body;
  body.name = name;
  body.mass = mass;
  body.position = position;
  body.geoms.push_back(MakeGeom(Shape::kBox, size, material));
  return body;
}

inline BodyDescription StaticBox(const std::string& name, const Eigen::Vector3d& size, const Eigen::Vector3d& position) {
  BodyDescription body = Box(name, size, 0.0, "PVC", position);
  body.dynamic = false;
  return body;
}

inline std::shared_ptr<const PhysicsModel> Compile(PhysicsDescription description) {
  return std::make_shared<const PhysicsModel>(std::move(description));
}

// Steps for `seconds`; fails the test at the first step that is not kOk.
inline void RunFor(PhysicsWorld& world, double seconds, const PhysicsParameters& parameters = {}) {
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(world.Step(kDt, parameters), StepStatus::kOk) << "step " << i << ": " << world.last_error();
  }
}

inline PhysicsParameters ZeroGravity() {
  PhysicsParameters p;
  p.gravity = Eigen::Vector3d::Zero();
  return p;
}

// Gravity tilted by `degrees` about z: the floor becomes a slope going down towards +x.
inline PhysicsParameters TiltedGravity(double degrees) {
  PhysicsParameters p;
  const double angle = degrees * kPi / 180.0;
  p.gravity = kG * Eigen::Vector3d(std::sin(angle), -std::cos(angle), 0.0);
  return p;
}

// A 0.1 kg bob whose centre is 0.2 m from a hinge at the origin about +z, hinged to the world.
inline PhysicsDescription Pendulum(bool limited, bool motorised) {
  PhysicsDescription d;
  d.bodies = {Box("Bob", {0.1, 0.02, 0.02}, 0.1, "ABS", {0.2, 0, 0})};
  JointDescription hinge;
  hinge.name = "Pivot";
  hinge.body1 = "Bob";
  hinge.axis = {0, 0, 1};
  hinge.limited = limited;
  hinge.lo = -0.5;
  hinge.hi = 0.5;
  hinge.motorised = motorised;
  d.joints.push_back(hinge);
  return d;
}

inline double BobAngle(const PhysicsWorld& world) {
  const Eigen::Vector3d p = world.body_state(0).position;
  return std::atan2(p.y(), p.x());
}

// Three motorised hinged boxes dropped tilted on a floor: contacts, limits, motors and friction all active. The
// first hinge turns about z, the second about `second_axis`: about y (the default) the chain bends out of its plane
// and, driven by Trajectory, its links touch each other as well as the floor; about z it stays planar and only
// touches the floor.
inline PhysicsDescription Chain(const Eigen::Vector3d& second_axis = Eigen::Vector3d::UnitY()) {
  PhysicsDescription d;
  d.bodies.push_back(Floor());
  for (int i = 0; i < 3; ++i) {
    BodyDescription link = Box("Link" + std::to_string(i), {0.1, 0.03, 0.05}, 0.1, i == 1 ? "Latex" : "ABS",
                               {0.11 * i, 0.2 + 0.03 * i, 0});
    link.orientation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 0, 1).normalized());
    d.bodies.push_back(link);
  }
  for (int i = 0; i < 2; ++i) {
    JointDescription hinge;
    hinge.name = "Hinge" + std::to_string(i);
    hinge.body1 = "Link" + std::to_string(i + 1);
    hinge.body2 = "Link" + std::to_string(i);
    hinge.anchor = {0.055 + 0.11 * i, 0.215 + 0.03 * i, 0};
    hinge.axis = i == 0 ? Eigen::Vector3d::UnitZ() : second_axis;
    hinge.limited = true;
    hinge.lo = -0.8;
    hinge.hi = 0.8;
    hinge.motorised = true;
    d.joints.push_back(hinge);
  }
  return d;
}

// Every coordinate of every link of the Chain (position, orientation, both velocities) after each of `steps`
// steps, with the motors driven.
inline std::vector<double> Trajectory(PhysicsWorld& world, int steps) {
  std::vector<double> out;
  for (int i = 0; i < steps; ++i) {
    world.SetJointMotor(0, 2.0 * std::sin(0.05 * i), 0.05);
    world.SetJointMotor(1, -1.0, 0.02);
    world.SetJointFriction(1, 0.001);
    EXPECT_EQ(world.Step(kDt, {}), StepStatus::kOk);
    for (int b = 1; b < 4; ++b) {
      const BodyState s = world.body_state(b);
      out.insert(out.end(), s.position.data(), s.position.data() + 3);
      out.insert(out.end(), s.orientation.coeffs().data(), s.orientation.coeffs().data() + 4);
      out.insert(out.end(), s.linear_velocity.data(), s.linear_velocity.data() + 3);
      out.insert(out.end(), s.angular_velocity.data(), s.angular_velocity.data() + 3);
    }
  }
  return out;
}

// A ball dropped on a static shelf at 0.3 m (top at 0.31 m) above the floor.
inline PhysicsDescription BallAboveShelf() {
  PhysicsDescription d;
  d.bodies = {Floor(), StaticBox("Shelf", {1, 0.02, 1}, {0, 0.3, 0}), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.6, 0})};
  return d;
}

}  // namespace orcs::physics::test_worlds
