#include "model/aseries/aseries_builder.h"

#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

#include "model/core/error.h"
#include "model/core/rotation.h"

namespace orcs::aseries {
namespace {

constexpr char kSource[] = "A-Series placement";

physics::GeomDescription BoxGeom(std::string name, const Eigen::Vector3d& size, const Eigen::Vector3d& offset,
                                 const Eigen::Quaterniond& rotation, std::string material, double mass,
                                 const Rgba& color) {
  physics::GeomDescription geom;
  geom.name = std::move(name);
  geom.shape = physics::Shape::kBox;
  geom.size = size;
  geom.offset = offset;
  geom.rotation = rotation;
  geom.material = std::move(material);
  geom.mass = mass;
  geom.rgba = color;
  return geom;
}

// The morphology's rigid placement in the world: rotate about the origin, then translate.
struct Placement {
  Eigen::Quaterniond rotation;
  Eigen::Vector3d translation;
  Eigen::Vector3d Point(const Eigen::Vector3d& p) const { return rotation * p + translation; }
  Eigen::Vector3d Direction(const Eigen::Vector3d& d) const { return rotation * d; }
};

Placement CheckPlacement(const ASeriesPlacement& placement) {
  if (placement.agent_name.empty()) {
    throw InputError(kSource, 0, "field 'agent_name' expected a non-empty name, found \"\"");
  }
  if (!placement.position.allFinite()) {
    throw InputError(kSource, 0, "field 'position' expected a finite position (m), found a non-finite one");
  }
  const double norm = placement.orientation.norm();
  if (!std::isfinite(norm) || norm < 1e-12) {
    throw InputError(kSource, 0, "field 'orientation' expected a finite non-zero quaternion, found another");
  }
  return {placement.orientation.normalized(), placement.position};
}

// Name of body `index` in the description; "" (the static world) for -1.
std::string BodyName(const physics::PhysicsDescription& description, int index) {
  return index < 0 ? std::string() : description.bodies[index].name;
}

}  // namespace

ASeriesLayout AddASeries(const ASeriesMorphology& morphology, const ASeriesPlacement& placement,
                         physics::PhysicsDescription& description) {
  const Placement place = CheckPlacement(placement);
  const std::string prefix = placement.agent_name + "/";
  ASeriesLayout layout;
  layout.agent_name = placement.agent_name;

  // Bodies, main boxes first: geoms[0] carries the box mass, which the physics layer lumps with the extra
  // geom masses at the box centre with the box's inertia shape (NERD's rule, quirk 2).
  std::unordered_map<std::string, int> body_index;  // morphology body name → description index
  for (const MorphologyBody& body : morphology.bodies) {
    physics::BodyDescription out;
    out.name = prefix + body.name;
    out.dynamic = true;
    out.mass = body.mass;
    out.position = place.Point(body.centre);
    out.orientation = place.rotation;
    physics::GeomDescription main_box = BoxGeom("", body.size, Eigen::Vector3d::Zero(),
                                                Eigen::Quaterniond::Identity(), body.material, 0.0, body.color);
    main_box.collides = !body.penetrable;  // the pelvis box (quirk 3)
    out.geoms.push_back(std::move(main_box));
    const int index = static_cast<int>(description.bodies.size());
    body_index.emplace(body.name, index);
    layout.bodies.push_back(index);
    description.bodies.push_back(std::move(out));
  }
  auto find_body = [&](const std::string& name, const std::string& where) {
    if (name.empty()) return -1;  // the static world
    const auto it = body_index.find(name);
    if (it == body_index.end()) {
      throw InputError("A-Series morphology", 0, where + " names unknown body \"" + name + "\"");
    }
    return it->second;
  };

  auto find_host = [&](const std::string& name, const std::string& where) {
    if (name.empty()) throw InputError("A-Series morphology", 0, where + " names no body");
    return find_body(name, where);
  };

  for (const MorphologyGeom& geom : morphology.geoms) {
    physics::BodyDescription& host = description.bodies[find_host(geom.host, "geom '" + geom.name + "'")];
    host.geoms.push_back(
        BoxGeom(geom.name, geom.size, geom.offset, Eigen::Quaterniond::Identity(), geom.material, geom.mass,
                geom.color));
  }

  for (const MorphologyBoard& board : morphology.boards) {
    const int host_index = find_host(board.host, "board '" + board.name + "'");
    physics::BodyDescription& host = description.bodies[host_index];
    const Eigen::Quaterniond rotation = board.rotation.normalized();
    ASeriesBoardLayout out;
    out.name = board.name;
    out.host_body = host_index;
    out.geom_in_body = static_cast<int>(host.geoms.size());
    out.local_position = board.position;
    out.local_rotation = rotation;
    out.axis1 = rotation * board.axis1;
    out.axis2 = rotation * board.axis2;
    layout.boards.push_back(std::move(out));
    host.geoms.push_back(BoxGeom(board.name, board.size, board.position, rotation, board.material, board.mass,
                                   board.color));
  }

  // Motorised hinges. The anchors are lifted with the bodies (quirk 1), so every axis sits where NERD's
  // formulas put it relative to its bodies; the axis direction is unchanged by the lift.
  const Eigen::Vector3d lift(0.0, morphology.lift, 0.0);
  for (const MorphologyMotor& motor : morphology.motors) {
    const std::string where = "motor '" + motor.name + "'";
    physics::JointDescription joint;
    joint.name = prefix + motor.name;
    joint.type = physics::JointType::kHinge;
    joint.body1 = BodyName(description, find_body(motor.first_body, where));
    joint.body2 = BodyName(description, find_body(motor.second_body, where));
    joint.anchor = place.Point(motor.axis_point1 + lift);
    joint.axis = place.Direction((motor.axis_point2 - motor.axis_point1).normalized());
    joint.limited = true;
    joint.lo = DegreesToRadians(motor.min_degrees);
    joint.hi = DegreesToRadians(motor.max_degrees);
    joint.motorised = true;
    layout.motors.push_back(static_cast<int>(description.joints.size()));
    description.joints.push_back(std::move(joint));
  }

  for (const MorphologyFixedJoint& fixed : morphology.fixed_joints) {
    const std::string where = "fixed joint '" + fixed.name + "'";
    physics::JointDescription joint;
    joint.name = prefix + fixed.name;
    joint.type = physics::JointType::kFixed;
    joint.body1 = BodyName(description, find_body(fixed.first_body, where));
    joint.body2 = BodyName(description, find_body(fixed.second_body, where));
    layout.fixed_joints.push_back(static_cast<int>(description.joints.size()));
    description.joints.push_back(std::move(joint));
  }

  // Body-pair exclusions. Entries narrowed to one geom (#4/#5, board × PDA) are left out: the physics layer
  // can only exclude whole bodies, and excluding the whole lower arm would let forearm and hand pass through
  // the PDA in reachable poses (docs/aseries-morphology.md).
  for (const MorphologyExclusion& exclusion : morphology.contact_exclusions) {
    const std::string where = "contact exclusion";
    const int first = find_host(exclusion.first, where);
    const int second = find_host(exclusion.second, where);
    if (!exclusion.first_geom.empty()) continue;
    description.contact_exclusions.emplace_back(description.bodies[first].name, description.bodies[second].name);
  }
  return layout;
}

}  // namespace orcs::aseries
