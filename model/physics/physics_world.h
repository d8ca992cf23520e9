// One simulated instance of a PhysicsModel (the engine part of MuJoCo's mjData): the interface every
// backend implements. Nothing above model/physics/ sees an engine type.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "model/physics/physics_model.h"
#include "model/physics/physics_parameters.h"

namespace orcs::physics {

/// Kinematic state of one body, world frame.
struct BodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               ///< body origin, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< body orientation
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();        ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       ///< rad/s
};

/// One contact point found in the last step, engine-independent.
struct Contact {
  int geom1 = -1;  ///< first geom as the collision routine ordered the pair (PhysicsModel::geom)
  int geom2 = -1;  ///< second geom
  int body1 = -1;  ///< owner of geom1
  int body2 = -1;  ///< owner of geom2
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< contact point, world, m
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();    ///< unit normal pointing into geom1, world
  double depth = 0.0;     ///< penetration depth, m
  bool excluded = false;  ///< the pair is on the exclusion list: reported, but no constraint was made
};

/// Outcome of one step. Anything but kOk leaves the world unusable until Reset().
enum class StepStatus {
  kOk,
  kUnstable,     ///< a position or velocity became non-finite or exceeded the speed limits
  kEngineError,  ///< the engine reported an error (ODE's error handler); see last_error()
};

class PhysicsWorld {
 public:
  virtual ~PhysicsWorld() = default;

  /// Restores the initial state of the model: initial poses, zero velocities, joints as created, motors off,
  /// no contacts. The same sequence of steps after a reset gives bit-identical results.
  virtual void Reset() = 0;

  /// Advances by dt seconds: collide → make contacts (materials, exclusions) → integrate → clear contacts →
  /// check for instability. The contacts found are kept until the next step.
  virtual StepStatus Step(double dt, const PhysicsParameters& parameters) = 0;

  /// Contacts found in the last step, in the order found.
  virtual const std::vector<Contact>& contacts() const = 0;
  /// Whether Step also tests the exclusion list's pairs and reports their contacts (Contact::excluded), as the
  /// original did for its collision events (spec/aseries.md §3b). On by default. Those pairs make no constraint
  /// either way, so turning it off leaves every motion bit-identical and only saves their collision tests (a
  /// third of a MuJoCo step for the A-Series on the leg-swing rig). Stays in force across Reset.
  virtual void SetReportExcludedContacts(bool report) = 0;

  virtual BodyState body_state(int body) const = 0;
  /// Moves a dynamic body (start-pose randomisation, tests). Velocities are set as given.
  virtual void SetBodyState(int body, const BodyState& state) = 0;

  /// Hinge angle relative to the initial pose, rad, and its rate, rad/s.
  virtual double joint_angle(int joint) const = 0;
  virtual double joint_rate(int joint) const = 0;
  /// Torque (N·m) the angular motor of a motorised hinge applied to body 1 about the axis in the last step;
  /// 0 for other joints and before the first step. Its product with joint_rate is the motor's power.
  virtual double joint_motor_torque(int joint) const = 0;

  /// Angular motor of a motorised hinge: drives the joint rate towards `velocity` (rad/s) with at most
  /// `max_torque` (N·m). Stays in force until changed.
  virtual void SetJointMotor(int joint, double velocity, double max_torque) = 0;
  /// Joint friction of a hinge: a brake towards zero rate with at most `max_torque` (N·m).
  virtual void SetJointFriction(int joint, double max_torque) = 0;
  /// Adds a torque (N·m) about a hinge's axis for the next step only (body1 gets +torque, body2 −torque).
  virtual void AddJointTorque(int joint, double torque) = 0;
  /// How far the angular motor of a motorised hinge yields under load: after the step the joint rate is
  /// u = velocity − compliance·τ while |τ| < max_torque, in rad/s per N·m. A compliant motor with target
  /// velocity c·(k·Δθ + d·v) and compliance c = 1/(k·dt + d) is an implicit spring k (N·m/rad) with damper
  /// d (N·m·s/rad), which is how the gear-elasticity effect works (docs/gap.md). 0 = the stiff default. Stays
  /// in force until changed or Reset.
  virtual void SetJointMotorCompliance(int joint, double compliance) = 0;
  /// Adds `inertia` (kg·m²) about `axis_in_body` (a unit vector in the body's frame, through its centre of
  /// mass) to a dynamic body's inertia, until Reset: the reflected rotor inertia of a geared motor.
  virtual void AddBodyInertia(int body, const Eigen::Vector3d& axis_in_body, double inertia) = 0;

  /// The engine's message after kEngineError, else "".
  virtual const std::string& last_error() const = 0;
  /// The compiled model this world simulates (masses, joint anchors and axes in the initial pose).
  virtual const PhysicsModel& model() const = 0;
};

}  // namespace orcs::physics
