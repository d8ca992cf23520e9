// The editable description of a physical world: bodies with their collision geoms, joints, the floor and
// the pairs of bodies that make no contact. Engine-independent (MuJoCo's mjSpec layer): the scene and the
// A-Series builders write it, PhysicsModel compiles and checks it, a backend (ode/) simulates it.
//
// Units: metres, kilograms, seconds, radians (angles in degrees exist only at the interfaces above this
// layer). The world frame is the ORCS one: +Y up, +Z forward.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace orcs::physics {

/// The collision shape of a geom.
enum class Shape {
  kBox,      ///< size = full edge lengths (x, y, z) in the geom frame, m
  kSphere,   ///< size.x() = radius, m
  kCapsule,  ///< size.x() = radius, size.y() = length of the cylinder part along the geom's local z, m
  kPlane,    ///< infinite plane through the body position with normal = body orientation × (0, 1, 0); static only
};

/// One collision geom rigidly attached to a body.
struct GeomDescription {
  std::string name;                                            ///< unique within its body; "" for the main geom
  Shape shape = Shape::kBox;                                   ///< collision shape
  Eigen::Vector3d size = Eigen::Vector3d::Zero();              ///< shape dimensions, m (see Shape)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();            ///< centre relative to the body frame, m
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< orientation relative to the body frame
  std::string material = "Default";                            ///< material name (MaterialTable); unknown names use the fallback rule
  double mass = 0.0;  ///< kg this extra geom adds to its body (ignored for geoms[0], whose mass is the body's)
  bool collides = true;  ///< false: penetrable, never collides (the A-Series pelvis box)
  /// Display colour red, green, blue, alpha, each 0…255 (MuJoCo's geom_rgba). Visual only: no engine reads it;
  /// recordings carry it to the viewer.
  std::array<int, 4> rgba = {255, 255, 255, 255};
  /// Display texture of the original ("Dynamixel", "Alu", "AccelBoard", or an XML object's name for one); "" for
  /// none. Visual only, like rgba: the viewer draws the known ones as simple patterns.
  std::string texture;
};

/// A rigid body. Dynamic bodies move; static ones are fixed in the world (their geoms have no ODE body).
struct BodyDescription {
  std::string name;        ///< unique in the world ("SecondSphere", "Humanoid/Right/Foot")
  bool dynamic = true;     ///< false: fixed in the world
  double mass = 0.0;       ///< kg of the main geom; must be > 0 for a dynamic body
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               ///< world position of the body frame, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< world orientation of the body frame
  /// geoms[0] is the main geom. Mass rule of the original (spec/aseries.md §2b): the inertia is that of a
  /// uniform solid of geoms[0]'s shape carrying the total mass (body mass + extra geom masses), centred at
  /// the body origin.
  std::vector<GeomDescription> geoms;
  /// Principal moments of inertia about the body origin along the body frame's x, y, z axes, kg·m²; zero = the
  /// mass rule above (a robot file's or a value's own inertia replaces it).
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();
  double static_friction = 0.0;   ///< fallback static friction coefficient (unknown materials), -
  double dynamic_friction = 0.0;  ///< fallback dynamic friction coefficient (unknown materials), -
  double elasticity = 0.05;       ///< fallback restitution factor (unknown materials), -
};

enum class JointType {
  kHinge,  ///< one rotational degree of freedom about `axis` through `anchor`
  kFixed,  ///< welds body1 to body2 in their initial relative pose
};

/// A joint between two bodies, or between a body and the static world.
struct JointDescription {
  std::string name;                                    ///< unique in the world ("Humanoid/Right/Knee")
  JointType type = JointType::kHinge;                  ///< kind of joint
  std::string body1;                                   ///< name of a dynamic body
  std::string body2;                                   ///< name of a dynamic body, or "" for the static world
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();    ///< hinge: a point on the axis, world, m
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();     ///< hinge: axis direction, world (normalised on compile)
  bool limited = false;  ///< hinge: has stops
  double lo = 0.0;       ///< hinge: lower stop, rad, relative to the initial pose (angle 0)
  double hi = 0.0;       ///< hinge: upper stop, rad
  bool motorised = false;  ///< hinge: carries an angular motor (PhysicsWorld::SetJointMotor)
};

/// A whole world, ready to compile.
struct PhysicsDescription {
  std::vector<BodyDescription> bodies;    ///< in creation order; indices are body ids
  std::vector<JointDescription> joints;   ///< in creation order; indices are joint ids
  /// Pairs of body names whose geoms collide (and are reported as contacts with `excluded` set) but create no
  /// contact constraint: the original's explicit collision-suppression list.
  std::vector<std::pair<std::string, std::string>> contact_exclusions;
};

}  // namespace orcs::physics
