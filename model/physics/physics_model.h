// The compiled, immutable physics model (MuJoCo's mjModel layer): a checked PhysicsDescription with every
// name resolved to an index. One model is shared by any number of worlds (one per evaluation).
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "model/physics/physics_description.h"

namespace orcs::physics {

/// A geom with its owner and resolved material.
struct GeomInfo {
  int body = -1;         ///< index of the owning body
  int index_in_body = 0;  ///< position in BodyDescription::geoms (0 = main geom)
  int material = -1;     ///< MaterialTable index, or MaterialTable::kUnknown
};

class PhysicsModel {
 public:
  /// Checks and compiles a description. Throws InputError naming the body, geom or joint and the field at fault
  /// (duplicate names, a dynamic body without positive mass, a non-positive size, a joint naming an unknown or
  /// static body, a zero axis, lo > hi, a plane on a dynamic body, an exclusion naming an unknown body).
  explicit PhysicsModel(PhysicsDescription description);

  const PhysicsDescription& description() const { return description_; }
  int body_count() const { return static_cast<int>(description_.bodies.size()); }
  int joint_count() const { return static_cast<int>(description_.joints.size()); }
  int geom_count() const { return static_cast<int>(geoms_.size()); }

  const BodyDescription& body(int index) const { return description_.bodies[index]; }
  const JointDescription& joint(int index) const { return description_.joints[index]; }
  /// Geoms are numbered body by body, in description order.
  const GeomInfo& geom(int index) const { return geoms_[index]; }
  /// Index of the first geom of a body.
  int first_geom(int body) const { return first_geom_[body]; }

  /// Index of a body or joint by name, or -1.
  int FindBody(std::string_view name) const;
  int FindJoint(std::string_view name) const;

  /// Body indices of a joint; body2 is -1 for the static world.
  int joint_body1(int joint) const { return joint_bodies_[joint].first; }
  int joint_body2(int joint) const { return joint_bodies_[joint].second; }

  /// Body mass plus the masses of its extra geoms, kg (0 for static bodies).
  double total_mass(int body) const { return total_mass_[body]; }

  /// True when the pair's collisions create no contact constraint (the exclusion list).
  bool contact_excluded(int body_a, int body_b) const;

 private:
  PhysicsDescription description_;
  std::vector<GeomInfo> geoms_;
  std::vector<int> first_geom_;
  std::vector<std::pair<int, int>> joint_bodies_;
  std::vector<double> total_mass_;
  std::vector<bool> excluded_;  // body_count² matrix, symmetric
};

}  // namespace orcs::physics
