#include "model/physics/gravity_load.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace orcs::physics {
namespace {

bool Holds(const std::vector<int>& bodies, int body) {
  return body >= 0 && std::find(bodies.begin(), bodies.end(), body) != bodies.end();
}

}  // namespace

GravityLoad::GravityLoad(const PhysicsModel& model, int joint, std::vector<int> load_bodies)
    : bodies_(std::move(load_bodies)) {
  const JointDescription& description = model.joint(joint);
  if (description.type != JointType::kHinge) {
    throw std::invalid_argument("GravityLoad: joint '" + description.name + "' is not a hinge");
  }
  const int body1 = model.joint_body1(joint);
  const int body2 = model.joint_body2(joint);
  if (Holds(bodies_, body1)) {
    carrier_ = body1;
    sense_ = 1.0;
  } else if (Holds(bodies_, body2)) {
    carrier_ = body2;
    sense_ = -1.0;
  } else {
    throw std::invalid_argument("GravityLoad: the load of joint '" + description.name + "' holds neither body");
  }
  for (int body : bodies_) mass_.push_back(model.total_mass(body));
  // The description's anchor and axis are the initial pose's, where the carrier is at its described pose.
  const BodyDescription& carrier = model.body(carrier_);
  const Eigen::Quaterniond to_carrier = carrier.orientation.normalized().conjugate();
  anchor_in_carrier_ = to_carrier * (description.anchor - carrier.position);
  axis_in_carrier_ = (to_carrier * description.axis).normalized();
}

double GravityLoad::Torque(const PhysicsWorld& world, const Eigen::Vector3d& gravity) const {
  const BodyState carrier = world.body_state(carrier_);
  const Eigen::Vector3d anchor = carrier.position + carrier.orientation * anchor_in_carrier_;
  const Eigen::Vector3d axis = carrier.orientation * axis_in_carrier_;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    moment += (world.body_state(bodies_[i]).position - anchor).cross(mass_[i] * gravity);
  }
  return sense_ * moment.dot(axis);
}

}  // namespace orcs::physics
