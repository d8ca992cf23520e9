// The MJCF (MuJoCo's XML) of a PhysicsModel: how the MuJoCo backend compiles a world, and what
// `--export-mjcf` writes for users and for benchmarks against raw MuJoCo. Generated, never hand-written: the
// PhysicsDescription stays the single source.
//
// Mapping (docs/model.md, "The MuJoCo backend"):
//   - static bodies' geoms sit in <worldbody> at their world pose; a plane's normal (the body's +y) becomes the
//     MuJoCo plane's local +z;
//   - dynamic bodies form trees: a body joined to the world is a root with that joint (or welded: no joint), any
//     other component's first body is a root with a <freejoint>, and every other body is nested under the body it
//     is joined to, with the joint in the child: hinges keep their axis, limits and anchor (the axis flipped when
//     the child is the joint's body2, so that the angle still measures body1 against body2), fixed joints weld by
//     nesting. A joint that would close a loop is refused (InputError naming it);
//   - inertia is the original's rule (uniform solid of geoms[0]'s shape with the total mass, centred at the body
//     origin), given explicitly; extra geoms only collide;
//   - every motorised hinge gets a motor: a fixed tendon on it named "motor:<joint>" whose friction loss (a
//     bounded velocity constraint) the world aims at the motor's target velocity;
//   - parent and child bodies collide (as in ODE); the exclusion list is written as <exclude> pairs
//     (MjcfOptions), and the world tests those pairs on its own when their collision events are wanted.
#pragma once

#include <string>

#include "model/physics/physics_model.h"

namespace orcs::physics {

/// Options of the generated model that the world sets at compile time.
struct MjcfOptions {
  double timestep = 0.01;          ///< s; the world overrides it per step
  bool implicit_integrator = false;  ///< MuJoCo's implicit-in-velocity integrator (else Euler, the default)
  int max_contacts = 0;         ///< MuJoCo's contact buffer (nconmax); 0 = sized from the model (MjcfContactBuffer)
  int max_constraint_rows = 0;  ///< MuJoCo's constraint buffer (njmax); 0 = sized from the model
  /// Write the exclusion list as <exclude> body pairs (a static body on it as its own jointless body), so that
  /// MuJoCo never tests those pairs. The world compiles with them and tests the pairs itself only to report
  /// their collision events (PhysicsWorld::SetReportExcludedContacts); `--export-mjcf` writes them, so that the
  /// exported model moves as the world does.
  bool exclusions = false;
};

/// The MJCF text of `model`. Throws InputError for a joint that closes a kinematic loop.
std::string ExportMjcf(const PhysicsModel& model, const MjcfOptions& options = {});

/// The buffer sizes the export chooses when MjcfOptions leaves them 0. MuJoCo 2.2 sizes its solver stack from
/// njmax quadratically: a fixed njmax of 5000 costs 1 GB and 0.6 s per world, while the A-Series uses at most 52
/// contacts and 170 constraint rows in its motions (docs/model.md). Contacts cost little: 8 per geom, at least
/// 200. Rows: per dynamic body 12 for its degrees of freedom (limit, motor, brake) and 16 for four resting
/// contacts of a pyramidal cone, at least 500 (the A-Series: 616).
int MjcfContactBuffer(const PhysicsModel& model);
int MjcfConstraintRows(const PhysicsModel& model);

/// The MJCF names the export gives: a dynamic or static body's geom `index_in_body` of body `body`.
std::string MjcfGeomName(const PhysicsModel& model, int geom);
/// A motorised hinge's motor tendon.
std::string MjcfMotorName(const PhysicsModel& model, int joint);

}  // namespace orcs::physics
