#include "model/physics/physics_model.h"

#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include "base/demand.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/physics/material_table.h"

namespace orcs::physics {
namespace {

// Shortest round-trip text of a number, for messages ("found 0", "found -0.5", "found nan").
std::string Num(double value) {
  std::array<char, 32> text{};
  const auto result = std::to_chars(text.data(), text.data() + text.size(), value);
  return std::string(text.data(), result.ptr);
}

std::string Vec(const Eigen::Vector3d& v) { return "(" + Num(v.x()) + ", " + Num(v.y()) + ", " + Num(v.z()) + ")"; }

std::string BodySource(const BodyDescription& body, int index) {
  return body.name.empty() ? "body #" + std::to_string(index) : "body " + text::Quote(body.name);
}

std::string GeomSource(const BodyDescription& body, int body_index, const GeomDescription& geom, int geom_index) {
  const std::string geom_part =
      geom.name.empty() ? "geom #" + std::to_string(geom_index) : "geom " + text::Quote(geom.name);
  return BodySource(body, body_index) + " " + geom_part;
}

std::string JointSource(const JointDescription& joint, int index) {
  return joint.name.empty() ? "joint #" + std::to_string(index) : "joint " + text::Quote(joint.name);
}

[[noreturn]] void Fail(const std::string& source, const std::string& field, const std::string& expected,
                       const std::string& found) {
  throw InputError(source, 0, "field " + text::Quote(field) + " expected " + expected + ", found " + found);
}

bool IsFinite(const Eigen::Vector3d& v) { return v.allFinite(); }

// Sizes and masses ODE can integrate: beyond these its mass check fails or inertias underflow. A micrometre to
// a thousand kilometres and a microgram to a million tonnes cover every world this project simulates.
constexpr double kMinSize = 1e-6;   // m
constexpr double kMaxSize = 1e6;    // m
constexpr double kMinMass = 1e-9;   // kg
constexpr double kMaxMass = 1e9;    // kg
bool SizeInRange(double size) { return size >= kMinSize && size <= kMaxSize; }

// A rotation must be finite and not zero; it is normalised in place.
void CheckRotation(Eigen::Quaterniond& q, const std::string& source, const std::string& field) {
  const double norm = q.norm();
  if (!std::isfinite(norm) || norm < 1e-12) {
    Fail(source, field, "a finite non-zero quaternion",
         "(w " + Num(q.w()) + ", x " + Num(q.x()) + ", y " + Num(q.y()) + ", z " + Num(q.z()) + ")");
  }
  q.normalize();
}

void CheckGeomSize(const GeomDescription& geom, const std::string& source) {
  const Eigen::Vector3d& s = geom.size;
  switch (geom.shape) {
    case Shape::kBox:
      if (!SizeInRange(s.minCoeff()) || !SizeInRange(s.maxCoeff())) {
        Fail(source, "size", "three edge lengths from 1e-6 to 1e6 m", Vec(s));
      }
      break;
    case Shape::kSphere:
      if (!SizeInRange(s.x())) Fail(source, "size", "a radius in x from 1e-6 to 1e6 m", Num(s.x()));
      break;
    case Shape::kCapsule:
      if (!SizeInRange(s.x())) Fail(source, "size", "a radius in x from 1e-6 to 1e6 m", Num(s.x()));
      if (!std::isfinite(s.y()) || !(s.y() >= 0.0)) {
        Fail(source, "size", "a non-negative cylinder length in y (m)", Num(s.y()));
      }
      break;
    case Shape::kPlane:
      break;  // infinite; size is unused
  }
}

void CheckGeom(GeomDescription& geom, const BodyDescription& body, const std::string& source) {
  if (geom.shape == Shape::kPlane && body.dynamic) {
    Fail(source, "shape", "a plane only on a static body (dynamic = false)", "a plane on a dynamic body");
  }
  CheckGeomSize(geom, source);
  if (!IsFinite(geom.offset)) Fail(source, "offset", "a finite position (m)", Vec(geom.offset));
  CheckRotation(geom.rotation, source, "rotation");
  if (!std::isfinite(geom.mass) || geom.mass < 0.0) Fail(source, "mass", "a non-negative mass (kg)", Num(geom.mass));
}

void CheckBody(BodyDescription& body, int index) {
  const std::string source = BodySource(body, index);
  if (body.name.empty()) Fail(source, "name", "a non-empty name", "\"\"");
  if (body.dynamic && !(body.mass >= kMinMass && body.mass <= kMaxMass)) {
    Fail(source, "mass", "a positive mass (kg) for a dynamic body, from 1e-9 to 1e9", Num(body.mass));
  }
  if (body.dynamic && body.geoms.empty()) {
    Fail(source, "geoms", "at least one geom for a dynamic body (geoms[0] shapes its inertia)", "none");
  }
  if (!IsFinite(body.position)) Fail(source, "position", "a finite position (m)", Vec(body.position));
  CheckRotation(body.orientation, source, "orientation");
  for (const auto& [field, value] : {std::pair{"static_friction", body.static_friction},
                                     std::pair{"dynamic_friction", body.dynamic_friction},
                                     std::pair{"elasticity", body.elasticity}}) {
    if (!std::isfinite(value) || value < 0.0) Fail(source, field, "a non-negative number", Num(value));
  }
  std::unordered_map<std::string, int> geom_names;
  for (int g = 0; g < static_cast<int>(body.geoms.size()); ++g) {
    GeomDescription& geom = body.geoms[g];
    const std::string geom_source = GeomSource(body, index, geom, g);
    if (!geom.name.empty() && !geom_names.emplace(geom.name, g).second) {
      Fail(geom_source, "name", "a name unique within the body", text::Quote(geom.name) + " used twice");
    }
    CheckGeom(geom, body, geom_source);
  }
}

// Resolves a joint's body name to a dynamic body index. `allow_world` admits "" as the static world (-1).
int ResolveJointBody(const std::unordered_map<std::string, int>& bodies, const PhysicsDescription& description,
                     const std::string& name, bool allow_world, const std::string& source, const char* field) {
  const char* expected = allow_world ? "the name of a dynamic body, or \"\" for the static world"
                                     : "the name of a dynamic body";
  if (name.empty()) {
    if (allow_world) return -1;
    Fail(source, field, expected, "\"\"");
  }
  const auto it = bodies.find(name);
  if (it == bodies.end()) Fail(source, field, expected, "unknown body " + text::Quote(name));
  if (!description.bodies[it->second].dynamic) Fail(source, field, expected, "static body " + text::Quote(name));
  return it->second;
}

void CheckHinge(JointDescription& joint, const std::string& source) {
  if (!IsFinite(joint.anchor)) Fail(source, "anchor", "a finite point (m)", Vec(joint.anchor));
  const double length = joint.axis.norm();
  if (!std::isfinite(length) || length < 1e-12) Fail(source, "axis", "a non-zero direction", Vec(joint.axis));
  joint.axis /= length;
  if (!joint.limited) return;
  // ODE's hinge stops only work within ±π.
  constexpr double kPi = std::numbers::pi;
  if (!std::isfinite(joint.lo) || joint.lo < -kPi) {
    Fail(source, "lo", "a lower stop within -pi..pi (rad)", Num(joint.lo));
  }
  if (!std::isfinite(joint.hi) || joint.hi > kPi) {
    Fail(source, "hi", "an upper stop within -pi..pi (rad)", Num(joint.hi));
  }
  if (joint.lo > joint.hi) {
    Fail(source, "lo", "lo <= hi (" + Num(joint.hi) + " rad)", Num(joint.lo));
  }
}

}  // namespace

PhysicsModel::PhysicsModel(PhysicsDescription description) : description_(std::move(description)) {
  const int bodies = body_count();
  std::unordered_map<std::string, int> body_index;
  total_mass_.assign(bodies, 0.0);
  first_geom_.assign(bodies, 0);
  for (int b = 0; b < bodies; ++b) {
    BodyDescription& body = description_.bodies[b];
    CheckBody(body, b);
    if (!body_index.emplace(body.name, b).second) {
      Fail(BodySource(body, b), "name", "a name unique in the world", text::Quote(body.name) + " used twice");
    }
    first_geom_[b] = static_cast<int>(geoms_.size());
    for (int g = 0; g < static_cast<int>(body.geoms.size()); ++g) {
      geoms_.push_back({b, g, MaterialTable::IndexOf(body.geoms[g].material)});
      if (body.dynamic && g > 0) total_mass_[b] += body.geoms[g].mass;
    }
    if (body.dynamic) total_mass_[b] += body.mass;
  }

  std::unordered_map<std::string, int> joint_names;
  for (int j = 0; j < joint_count(); ++j) {
    JointDescription& joint = description_.joints[j];
    const std::string source = JointSource(joint, j);
    if (joint.name.empty()) Fail(source, "name", "a non-empty name", "\"\"");
    if (!joint_names.emplace(joint.name, j).second) {
      Fail(source, "name", "a name unique in the world", text::Quote(joint.name) + " used twice");
    }
    const int b1 = ResolveJointBody(body_index, description_, joint.body1, false, source, "body1");
    const int b2 = ResolveJointBody(body_index, description_, joint.body2, true, source, "body2");
    if (b1 == b2) Fail(source, "body2", "a body other than body1", text::Quote(joint.body2) + " again");
    if (joint.type == JointType::kHinge) {
      CheckHinge(joint, source);
    } else if (joint.motorised) {
      Fail(source, "motorised", "false for a fixed joint", "true");
    }
    joint_bodies_.emplace_back(b1, b2);
  }

  excluded_.assign(static_cast<std::size_t>(bodies) * static_cast<std::size_t>(bodies), false);
  for (int e = 0; e < static_cast<int>(description_.contact_exclusions.size()); ++e) {
    const auto& [name_a, name_b] = description_.contact_exclusions[e];
    const std::string source = "contact exclusion #" + std::to_string(e) + " (" + text::Quote(name_a) + ", " + text::Quote(name_b) + ")";
    const auto a = body_index.find(name_a);
    if (a == body_index.end()) Fail(source, "first", "the name of a body", "unknown body " + text::Quote(name_a));
    const auto b = body_index.find(name_b);
    if (b == body_index.end()) Fail(source, "second", "the name of a body", "unknown body " + text::Quote(name_b));
    excluded_[static_cast<std::size_t>(a->second) * bodies + b->second] = true;
    excluded_[static_cast<std::size_t>(b->second) * bodies + a->second] = true;
  }
}

int PhysicsModel::FindBody(std::string_view name) const {
  for (int b = 0; b < body_count(); ++b) {
    if (description_.bodies[b].name == name) return b;
  }
  return -1;
}

int PhysicsModel::FindJoint(std::string_view name) const {
  for (int j = 0; j < joint_count(); ++j) {
    if (description_.joints[j].name == name) return j;
  }
  return -1;
}

bool PhysicsModel::contact_excluded(int body_a, int body_b) const {
  ORCS_DEMAND(body_a >= 0 && body_a < body_count() && body_b >= 0 && body_b < body_count());
  return excluded_[static_cast<std::size_t>(body_a) * body_count() + body_b];
}

}  // namespace orcs::physics
