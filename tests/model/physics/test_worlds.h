// Small worlds for the physics backends' tests (tests/model/physics/ode/, tests/model/physics/mujoco/): a floor,
// spheres and boxes, a hinged pendulum, a ball over a shelf, and stepping helpers.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

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

// A ball dropped on a static shelf at 0.3 m (top at 0.31 m) above the floor.
inline PhysicsDescription BallAboveShelf() {
  PhysicsDescription d;
  d.bodies = {Floor(), StaticBox("Shelf", {1, 0.02, 1}, {0, 0.3, 0}), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.6, 0})};
  return d;
}

}  // namespace orcs::physics::test_worlds
