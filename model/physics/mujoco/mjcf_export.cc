#include "model/physics/mujoco/mjcf_export.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "base/demand.h"
#include "model/core/error.h"

namespace orcs::physics {
namespace {

// The stiffest constraint impedance MuJoCo allows, for the friction brake and the motor: softer ones let a held
// joint creep.
constexpr const char* kStiffImpedance = "0.9999 0.9999 0.001";

// Numbers printed so that MuJoCo reads back the same double.
std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::string Vector(const Eigen::Vector3d& v) { return Number(v.x()) + " " + Number(v.y()) + " " + Number(v.z()); }

std::string Quaternion(const Eigen::Quaterniond& q) {  // MuJoCo: w x y z
  return Number(q.w()) + " " + Number(q.x()) + " " + Number(q.y()) + " " + Number(q.z());
}

// The kinematic trees of the dynamic bodies (see the header): who hangs under whom, by which joint.
struct Forest {
  std::vector<int> parent;        ///< body → its parent body, −1 for a root (or a static body)
  std::vector<int> joint;         ///< body → the joint to its parent (or to the world), −1 for none (free root)
  std::vector<std::vector<int>> children;
  std::vector<int> roots;         ///< in creation order of their discovery
};

class ForestBuilder {
 public:
  explicit ForestBuilder(const PhysicsModel& model)
      : model_(model),
        reached_(model.body_count(), false),
        used_(model.joint_count(), false),
        joints_of_(model.body_count()) {
    forest_.parent.assign(model.body_count(), -1);
    forest_.joint.assign(model.body_count(), -1);
    forest_.children.resize(model.body_count());
    for (int j = 0; j < model.joint_count(); ++j) {
      joints_of_[model.joint_body1(j)].push_back(j);
      if (model.joint_body2(j) >= 0) joints_of_[model.joint_body2(j)].push_back(j);
    }
  }

  Forest Build() {
    for (int j = 0; j < model_.joint_count(); ++j) {  // bodies joined to the world are roots with that joint
      if (model_.joint_body2(j) >= 0) continue;
      const int body = model_.joint_body1(j);
      if (reached_[body]) Loop(j);
      used_[j] = true;
      AddRoot(body, j);
    }
    for (int b = 0; b < model_.body_count(); ++b) {
      if (model_.body(b).dynamic && !reached_[b]) AddRoot(HeaviestJoinedTo(b), -1);
    }
    return std::move(forest_);
  }

 private:
  void AddRoot(int body, int joint) {
    forest_.roots.push_back(body);
    forest_.joint[body] = joint;
    reached_[body] = true;
    Grow(body);
  }

  // Depth first: every unused joint of `body` hangs its other body under it.
  void Grow(int body) {
    for (int j : joints_of_[body]) {
      if (used_[j]) continue;
      used_[j] = true;
      const int other = model_.joint_body1(j) == body ? model_.joint_body2(j) : model_.joint_body1(j);
      if (other < 0 || reached_[other]) Loop(j);
      reached_[other] = true;
      forest_.parent[other] = body;
      forest_.joint[other] = j;
      forest_.children[body].push_back(other);
      Grow(other);
    }
  }

  // The heaviest body of `body`'s group (ties: the first): a free robot hangs from its trunk, not from a foot,
  // which keeps MuJoCo's joint-space inertia well conditioned.
  int HeaviestJoinedTo(int body) const {
    std::vector<bool> seen(model_.body_count(), false);
    std::vector<int> stack{body};
    seen[body] = true;
    int heaviest = body;
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      if (model_.total_mass(b) > model_.total_mass(heaviest) ||
          (model_.total_mass(b) == model_.total_mass(heaviest) && b < heaviest)) {
        heaviest = b;
      }
      for (int j : joints_of_[b]) {
        for (int other : {model_.joint_body1(j), model_.joint_body2(j)}) {
          if (other >= 0 && !seen[other]) {
            seen[other] = true;
            stack.push_back(other);
          }
        }
      }
    }
    return heaviest;
  }

  [[noreturn]] void Loop(int joint) const {
    throw InputError("joint '" + model_.joint(joint).name +
                     "' closes a kinematic loop, which the MuJoCo backend cannot build (use ODE)");
  }

  const PhysicsModel& model_;
  std::vector<bool> reached_;
  std::vector<bool> used_;
  std::vector<std::vector<int>> joints_of_;
  Forest forest_;
};

// The original's mass rule with ODE's formulas (dMassSet*Total): inertia about the body origin, body frame.
Eigen::Matrix3d MainGeomInertia(const GeomDescription& geom, double mass) {
  const Eigen::Vector3d& s = geom.size;
  Eigen::Vector3d diagonal;
  switch (geom.shape) {
    case Shape::kBox:
      diagonal = mass / 12.0 * Eigen::Vector3d(s.y() * s.y() + s.z() * s.z(), s.x() * s.x() + s.z() * s.z(),
                                               s.x() * s.x() + s.y() * s.y());
      break;
    case Shape::kSphere:
      diagonal = Eigen::Vector3d::Constant(0.4 * mass * s.x() * s.x());
      break;
    case Shape::kCapsule: {
      const double r = s.x(), l = s.y();
      const double cylinder = std::numbers::pi * r * r * l, caps = 4.0 / 3.0 * std::numbers::pi * r * r * r;
      const double m1 = mass * cylinder / (cylinder + caps), m2 = mass * caps / (cylinder + caps);
      const double across = m1 * (0.25 * r * r + l * l / 12.0) + m2 * (0.4 * r * r + 0.375 * r * l + 0.25 * l * l);
      diagonal = Eigen::Vector3d(across, across, (0.5 * m1 + 0.4 * m2) * r * r);
      break;
    }
    case Shape::kPlane:
      ORCS_UNREACHABLE("PhysicsModel refuses a plane on a dynamic body");
      diagonal.setZero();
  }
  const Eigen::Matrix3d rotation = geom.rotation.normalized().toRotationMatrix();
  return rotation * diagonal.asDiagonal() * rotation.transpose();
}

}  // namespace

int MjcfContactBuffer(const PhysicsModel& model) { return std::max(200, 8 * model.geom_count()); }

int MjcfConstraintRows(const PhysicsModel& model) {
  int bodies = 0;
  for (int b = 0; b < model.body_count(); ++b) bodies += model.body(b).dynamic ? 1 : 0;
  return std::max(500, 28 * bodies);
}

namespace {

class MjcfWriter {
 public:
  MjcfWriter(const PhysicsModel& model, const MjcfOptions& options)
      : model_(model), options_(options), forest_(ForestBuilder(model).Build()) {}

  std::string Write() {
    tinyxml2::XMLElement* root = document_.NewElement("mujoco");
    root->SetAttribute("model", "orcs");
    document_.InsertEndChild(root);
    WriteHeader(root);
    tinyxml2::XMLElement* world = Child(root, "worldbody");
    for (int b = 0; b < model_.body_count(); ++b) {
      if (!model_.body(b).dynamic) WriteStaticBody(world, b);
    }
    for (int body : forest_.roots) WriteBody(world, body, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
    WriteMotors(root);
    if (options_.exclusions) WriteExclusions(root);
    tinyxml2::XMLPrinter printer;
    document_.Print(&printer);
    return printer.CStr();
  }

 private:
  tinyxml2::XMLElement* Child(tinyxml2::XMLElement* parent, const char* name) {
    tinyxml2::XMLElement* element = document_.NewElement(name);
    parent->InsertEndChild(element);
    return element;
  }

  void WriteHeader(tinyxml2::XMLElement* root) {
    tinyxml2::XMLElement* compiler = Child(root, "compiler");
    compiler->SetAttribute("angle", "radian");
    compiler->SetAttribute("inertiafromgeom", "false");
    tinyxml2::XMLElement* option = Child(root, "option");
    option->SetAttribute("timestep", Number(options_.timestep).c_str());
    option->SetAttribute("gravity", "0 -9.81 0");  // ORCS's frame: +y up
    option->SetAttribute("integrator", options_.implicit_integrator ? "implicit" : "Euler");
    Child(option, "flag")->SetAttribute("filterparent", "disable");  // jointed bodies collide, as in ODE
    tinyxml2::XMLElement* size = Child(root, "size");
    size->SetAttribute("nconmax", options_.max_contacts > 0 ? options_.max_contacts : MjcfContactBuffer(model_));
    size->SetAttribute("njmax",
                       options_.max_constraint_rows > 0 ? options_.max_constraint_rows : MjcfConstraintRows(model_));
    tinyxml2::XMLElement* geom_default = Child(Child(root, "default"), "geom");
    geom_default->SetAttribute("condim", 3);
  }

  // `parent_position` / `parent_orientation`: the world pose of the frame the element is written in.
  void WriteBody(tinyxml2::XMLElement* parent, int b, const Eigen::Vector3d& parent_position,
                 const Eigen::Quaterniond& parent_orientation) {
    const BodyDescription& body = model_.body(b);
    const Eigen::Quaterniond orientation = body.orientation.normalized();
    const Eigen::Quaterniond inverse = parent_orientation.conjugate();
    tinyxml2::XMLElement* element = Child(parent, "body");
    element->SetAttribute("name", body.name.c_str());
    element->SetAttribute("pos", Vector(inverse * (body.position - parent_position)).c_str());
    element->SetAttribute("quat", Quaternion(inverse * orientation).c_str());
    WriteInertial(element, b);
    const int joint = forest_.joint[b];
    if (joint < 0) {
      Child(element, "freejoint")->SetAttribute("name", (body.name + "#free").c_str());
    } else if (model_.joint(joint).type == JointType::kHinge) {
      WriteHinge(element, b, joint);
    }  // a fixed joint welds by nesting
    WriteGeoms(element, b, body.position, orientation);
    for (int child : forest_.children[b]) WriteBody(element, child, body.position, orientation);
  }

  void WriteInertial(tinyxml2::XMLElement* element, int b) {
    const Eigen::Vector3d& given = model_.body(b).inertia;  // its own inertia, else the rule's
    const Eigen::Matrix3d inertia = given.isZero(0.0) ? MainGeomInertia(model_.body(b).geoms[0], model_.total_mass(b))
                                                      : Eigen::Matrix3d(given.asDiagonal());
    tinyxml2::XMLElement* inertial = Child(element, "inertial");
    inertial->SetAttribute("pos", "0 0 0");
    inertial->SetAttribute("mass", Number(model_.total_mass(b)).c_str());
    inertial->SetAttribute("fullinertia", (Number(inertia(0, 0)) + " " + Number(inertia(1, 1)) + " " +
                                           Number(inertia(2, 2)) + " " + Number(inertia(0, 1)) + " " +
                                           Number(inertia(0, 2)) + " " + Number(inertia(1, 2)))
                                              .c_str());
  }

  // The hinge in the child's frame; its angle measures body1 against body2 whichever of them is the child.
  void WriteHinge(tinyxml2::XMLElement* element, int child, int j) {
    const JointDescription& joint = model_.joint(j);
    const BodyDescription& body = model_.body(child);
    const double sign = model_.joint_body1(j) == child ? 1.0 : -1.0;
    const Eigen::Quaterniond to_body = body.orientation.normalized().conjugate();
    tinyxml2::XMLElement* hinge = Child(element, "joint");
    hinge->SetAttribute("name", joint.name.c_str());
    hinge->SetAttribute("type", "hinge");
    // A friction brake (frictionloss) as stiff as MuJoCo allows: soft constraints let a held joint creep.
    hinge->SetAttribute("solimpfriction", kStiffImpedance);
    hinge->SetAttribute("pos", Vector(to_body * (joint.anchor - body.position)).c_str());
    hinge->SetAttribute("axis", Vector(sign * (to_body * joint.axis.normalized())).c_str());
    if (joint.limited) {
      hinge->SetAttribute("limited", "true");
      const double lo = sign > 0 ? joint.lo : -joint.hi, hi = sign > 0 ? joint.hi : -joint.lo;
      hinge->SetAttribute("range", (Number(lo) + " " + Number(hi)).c_str());
    }
  }

  // `position` / `orientation`: the world pose of the frame the geoms are written in (identity: world).
  void WriteGeoms(tinyxml2::XMLElement* element, int b, const Eigen::Vector3d& frame_position,
                  const Eigen::Quaterniond& frame_orientation) {
    const BodyDescription& body = model_.body(b);
    // Static geoms are written in the world frame at the body's pose; dynamic ones in their body's frame.
    const Eigen::Quaterniond body_orientation = body.orientation.normalized();
    const Eigen::Quaterniond to_frame = frame_orientation.conjugate();
    for (std::size_t k = 0; k < body.geoms.size(); ++k) {
      const GeomDescription& geom = body.geoms[k];
      const Eigen::Vector3d world_position = body.position + body_orientation * geom.offset;
      Eigen::Quaterniond world_rotation = body_orientation * geom.rotation.normalized();
      tinyxml2::XMLElement* g = Child(element, "geom");
      g->SetAttribute("name", MjcfGeomName(model_, model_.first_geom(b) + static_cast<int>(k)).c_str());
      WriteShape(g, geom, world_rotation);
      g->SetAttribute("pos", Vector(to_frame * (world_position - frame_position)).c_str());
      g->SetAttribute("quat", Quaternion(to_frame * world_rotation).c_str());
      if (!geom.collides) {
        g->SetAttribute("contype", 0);
        g->SetAttribute("conaffinity", 0);
      }
      g->SetAttribute("rgba", (Number(geom.rgba[0] / 255.0) + " " + Number(geom.rgba[1] / 255.0) + " " +
                               Number(geom.rgba[2] / 255.0) + " " + Number(geom.rgba[3] / 255.0))
                                  .c_str());
    }
  }

  // A plane's normal is its body's +y in ORCS and the geom's +z in MuJoCo: turned by −90° about x.
  static void WriteShape(tinyxml2::XMLElement* g, const GeomDescription& geom, Eigen::Quaterniond& rotation) {
    const Eigen::Vector3d& s = geom.size;
    switch (geom.shape) {
      case Shape::kBox:
        g->SetAttribute("type", "box");
        g->SetAttribute("size", Vector(0.5 * s).c_str());
        break;
      case Shape::kSphere:
        g->SetAttribute("type", "sphere");
        g->SetAttribute("size", Number(s.x()).c_str());
        break;
      case Shape::kCapsule:
        g->SetAttribute("type", "capsule");
        g->SetAttribute("size", (Number(s.x()) + " " + Number(0.5 * s.y())).c_str());
        break;
      case Shape::kPlane:
        g->SetAttribute("type", "plane");
        g->SetAttribute("size", "0 0 1");
        rotation = rotation * Eigen::Quaterniond(Eigen::AngleAxisd(-0.5 * std::numbers::pi, Eigen::Vector3d::UnitX()));
        break;
    }
  }

  // A motorised hinge's motor is a fixed tendon on it with friction loss: MuJoCo's bounded velocity constraint,
  // which the world turns towards the motor's target velocity each step (mujoco_world.cc, ServoReferences).
  // Its bound, the motor's torque limit, is set per step; 0 (no constraint row) until then.
  void WriteMotors(tinyxml2::XMLElement* root) {
    tinyxml2::XMLElement* tendons = nullptr;
    for (int j = 0; j < model_.joint_count(); ++j) {
      const JointDescription& joint = model_.joint(j);
      if (joint.type != JointType::kHinge || !joint.motorised) continue;
      if (tendons == nullptr) tendons = Child(root, "tendon");
      tinyxml2::XMLElement* motor = Child(tendons, "fixed");
      motor->SetAttribute("name", MjcfMotorName(model_, j).c_str());
      motor->SetAttribute("frictionloss", "0");
      motor->SetAttribute("solimpfriction", kStiffImpedance);
      tinyxml2::XMLElement* on = Child(motor, "joint");
      on->SetAttribute("joint", joint.name.c_str());
      on->SetAttribute("coef", "1");
    }
  }

  // A static body's geoms sit in the world body at their world pose. A static body on the written exclusion
  // list is its own jointless body (welded to the world) instead, so that an exclusion can name it alone.
  void WriteStaticBody(tinyxml2::XMLElement* world, int b) {
    if (!options_.exclusions || !OnExclusionList(b)) {
      WriteGeoms(world, b, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
      return;
    }
    const BodyDescription& body = model_.body(b);
    const Eigen::Quaterniond orientation = body.orientation.normalized();
    tinyxml2::XMLElement* element = Child(world, "body");
    element->SetAttribute("name", body.name.c_str());
    element->SetAttribute("pos", Vector(body.position).c_str());
    element->SetAttribute("quat", Quaternion(orientation).c_str());
    WriteGeoms(element, b, body.position, orientation);
  }

  bool OnExclusionList(int b) const {
    for (int other = 0; other < model_.body_count(); ++other) {
      if (other != b && model_.contact_excluded(b, other)) return true;
    }
    return false;
  }

  // The exclusion list as MuJoCo <exclude> body pairs: MuJoCo then never tests those bodies against each other.
  void WriteExclusions(tinyxml2::XMLElement* root) {
    tinyxml2::XMLElement* contact = nullptr;
    for (int a = 0; a < model_.body_count(); ++a) {
      for (int b = a + 1; b < model_.body_count(); ++b) {
        if (!model_.contact_excluded(a, b)) continue;
        if (contact == nullptr) contact = Child(root, "contact");
        tinyxml2::XMLElement* exclude = Child(contact, "exclude");
        exclude->SetAttribute("body1", model_.body(a).name.c_str());
        exclude->SetAttribute("body2", model_.body(b).name.c_str());
      }
    }
  }

  const PhysicsModel& model_;
  const MjcfOptions& options_;
  Forest forest_;
  tinyxml2::XMLDocument document_;
};

}  // namespace

std::string ExportMjcf(const PhysicsModel& model, const MjcfOptions& options) {
  return MjcfWriter(model, options).Write();
}

std::string MjcfGeomName(const PhysicsModel& model, int geom) {
  const GeomInfo& info = model.geom(geom);
  return model.body(info.body).name + "#" + std::to_string(info.index_in_body);
}

std::string MjcfMotorName(const PhysicsModel& model, int joint) { return "motor:" + model.joint(joint).name; }

}  // namespace orcs::physics
