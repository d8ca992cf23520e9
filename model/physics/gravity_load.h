// The torque gravity exerts about a hinge on the bodies one side of it carries (the load a joint's motor holds):
// Σ m_b·((c_b − a) × g)·n over those bodies, with a and n the hinge's anchor and axis where the bodies are now.
// Engine-independent: it reads the model's masses and the world's body poses (centre of mass = body origin, the
// mass rule of spec/aseries.md §2b). Contacts and the other bodies' pull are not part of it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "model/physics/physics_world.h"

namespace orcs::physics {

class GravityLoad {
 public:
  /// `load_bodies` are the bodies on one side of hinge `joint`, which must include one of its two bodies (the
  /// side whose pose carries the anchor and axis). Throws std::invalid_argument for a joint that is not a hinge or
  /// a load that holds neither of its bodies.
  GravityLoad(const PhysicsModel& model, int joint, std::vector<int> load_bodies);

  /// N·m, in the joint angle's sense: positive gravity turns the joint angle up (PhysicsWorld::joint_angle).
  /// `gravity` is the world's acceleration of gravity, m/s² (y up: (0, −9.81, 0)).
  double Torque(const PhysicsWorld& world, const Eigen::Vector3d& gravity) const;

 private:
  std::vector<int> bodies_;   // the load's bodies
  std::vector<double> mass_;  // kg of each, total (extra geoms included)
  int carrier_ = -1;          // the joint's body among them: its pose carries the anchor and the axis
  Eigen::Vector3d anchor_in_carrier_ = Eigen::Vector3d::Zero();  // m, the hinge anchor in the carrier's frame
  Eigen::Vector3d axis_in_carrier_ = Eigen::Vector3d::UnitX();   // unit, the hinge axis in the carrier's frame
  double sense_ = 1.0;  // +1: the load is on body 1's side (the angle is body 1's about the axis), −1: body 2's
};

}  // namespace orcs::physics
