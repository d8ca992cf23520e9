#include "model/aseries/aseries_builder.h"

#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

#include "model/core/error.h"
#include "model/core/rotation.h"
#include "model/core/text.h"

namespace orcs::aseries {
namespace {

constexpr char kSource[] = "A-Series placement";

physics::GeomDescription BoxGeom(std::string name, const Eigen::Vector3d& size, const Eigen::Vector3d& offset,
                                 const Eigen::Quaterniond& rotation, std::string material, double mass,
                                 const Rgba& color, std::string texture) {
  physics::GeomDescription geom;
  geom.name = std::move(name);
  geom.shape = physics::Shape::kBox;
  geom.size = size;
  geom.offset = offset;
  geom.rotation = rotation;
  geom.material = std::move(material);
  geom.mass = mass;
  geom.rgba = color;
  geom.texture = std::move(texture);
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

// One A-Series added to a description, stage by stage; body_index maps morphology body names to description
// indices once the bodies exist.
class Assembly {
 public:
  Assembly(const ASeriesMorphology& morphology, const ASeriesPlacement& placement,
           physics::PhysicsDescription& description, ASeriesLayout& layout)
      : morphology_(morphology), place_(CheckPlacement(placement)), prefix_(placement.agent_name + "/"),
        description_(description), layout_(layout) {
    layout_.agent_name = placement.agent_name;
  }

  // Bodies, main boxes first: geoms[0] carries the box mass, which the physics layer lumps with the extra
  // geom masses at the box centre with the box's inertia shape (NERD's rule, quirk 2).
  void AddBodies() {
    for (const MorphologyBody& body : morphology_.bodies) {
      physics::BodyDescription out;
      out.name = prefix_ + body.name;
      out.dynamic = true;
      out.mass = body.mass;
      out.inertia = body.inertia;
      out.position = place_.Point(body.centre);
      out.orientation = place_.rotation;
      physics::GeomDescription main_box = BoxGeom("", body.size, Eigen::Vector3d::Zero(),
                                                  Eigen::Quaterniond::Identity(), body.material, 0.0, body.color,
                                                  body.texture);
      main_box.collides = !body.penetrable;  // the pelvis box (quirk 3)
      out.geoms.push_back(std::move(main_box));
      const int index = static_cast<int>(description_.bodies.size());
      body_index_.emplace(body.name, index);
      layout_.bodies.push_back(index);
      description_.bodies.push_back(std::move(out));
    }
  }

  void AddGeoms() {
    for (const MorphologyGeom& geom : morphology_.geoms) {
      physics::BodyDescription& host = description_.bodies[FindHost(geom.host, "geom " + text::Quote(geom.name))];
      host.geoms.push_back(BoxGeom(geom.name, geom.size, geom.offset, Eigen::Quaterniond::Identity(),
                                   geom.material, geom.mass, geom.color, geom.texture));
    }
  }

  void AddBoards() {
    for (const MorphologyBoard& board : morphology_.boards) {
      const int host_index = FindHost(board.host, "board " + text::Quote(board.name));
      physics::BodyDescription& host = description_.bodies[host_index];
      const Eigen::Quaterniond rotation = board.rotation.normalized();
      ASeriesBoardLayout out;
      out.name = board.name;
      out.host_body = host_index;
      out.geom_in_body = static_cast<int>(host.geoms.size());
      out.local_position = board.position;
      out.local_rotation = rotation;
      out.axis1 = rotation * board.axis1;
      out.axis2 = rotation * board.axis2;
      layout_.boards.push_back(std::move(out));
      host.geoms.push_back(BoxGeom(board.name, board.size, board.position, rotation, board.material, board.mass,
                                   board.color, board.texture));
    }
  }

  // Motorised hinges. The anchors are lifted with the bodies (quirk 1), so every axis sits where NERD's
  // formulas put it relative to its bodies; the axis direction is unchanged by the lift.
  void AddMotors() {
    const Eigen::Vector3d lift(0.0, morphology_.lift, 0.0);
    for (const MorphologyMotor& motor : morphology_.motors) {
      physics::JointDescription joint =
          JointBetween(motor.name, physics::JointType::kHinge, motor.first_body, motor.second_body, "motor");
      joint.anchor = place_.Point(motor.axis_point1 + lift);
      joint.axis = place_.Direction((motor.axis_point2 - motor.axis_point1).normalized());
      joint.limited = true;
      joint.lo = DegreesToRadians(motor.min_degrees);
      joint.hi = DegreesToRadians(motor.max_degrees);
      joint.motorised = true;
      layout_.motors.push_back(static_cast<int>(description_.joints.size()));
      description_.joints.push_back(std::move(joint));
    }
  }

  void AddFixedJoints() {
    for (const MorphologyFixedJoint& fixed : morphology_.fixed_joints) {
      layout_.fixed_joints.push_back(static_cast<int>(description_.joints.size()));
      description_.joints.push_back(
          JointBetween(fixed.name, physics::JointType::kFixed, fixed.first_body, fixed.second_body, "fixed joint"));
    }
  }

  // Body-pair exclusions. Entries narrowed to one geom (#4/#5, board × PDA) are left out: the physics layer
  // can only exclude whole bodies, and excluding the whole lower arm would let forearm and hand pass through
  // the PDA in reachable poses (docs/aseries-morphology.md).
  void AddExclusions() {
    for (const MorphologyExclusion& exclusion : morphology_.contact_exclusions) {
      const int first = FindHost(exclusion.first, "contact exclusion");
      const int second = FindHost(exclusion.second, "contact exclusion");
      if (!exclusion.first_geom.empty()) continue;
      description_.contact_exclusions.emplace_back(description_.bodies[first].name,
                                                   description_.bodies[second].name);
    }
  }

 private:
  // The description index of a morphology body; -1 (the static world) for "".
  int FindBody(const std::string& name, const std::string& where) const {
    if (name.empty()) return -1;
    const auto it = body_index_.find(name);
    if (it == body_index_.end()) {
      throw InputError("A-Series morphology", 0, where + " names unknown body \"" + name + "\"");
    }
    return it->second;
  }

  // Like FindBody, but the static world is no host.
  int FindHost(const std::string& name, const std::string& where) const {
    if (name.empty()) throw InputError("A-Series morphology", 0, where + " names no body");
    return FindBody(name, where);
  }

  physics::JointDescription JointBetween(const std::string& name, physics::JointType type, const std::string& first,
                                         const std::string& second, const std::string& kind) const {
    const std::string where = kind + " " + text::Quote(name);
    physics::JointDescription joint;
    joint.name = prefix_ + name;
    joint.type = type;
    joint.body1 = BodyName(description_, FindBody(first, where));
    joint.body2 = BodyName(description_, FindBody(second, where));
    return joint;
  }

  const ASeriesMorphology& morphology_;
  const Placement place_;
  const std::string prefix_;                         ///< "<agent>/", prefixed to body and joint names
  physics::PhysicsDescription& description_;
  ASeriesLayout& layout_;
  std::unordered_map<std::string, int> body_index_;  ///< morphology body name → description index
};

}  // namespace

ASeriesLayout AddASeries(const ASeriesMorphology& morphology, const ASeriesPlacement& placement,
                         physics::PhysicsDescription& description) {
  ASeriesLayout layout;
  Assembly assembly(morphology, placement, description, layout);
  assembly.AddBodies();
  assembly.AddGeoms();
  assembly.AddBoards();
  assembly.AddMotors();
  assembly.AddFixedJoints();
  assembly.AddExclusions();
  return layout;
}

}  // namespace orcs::aseries
