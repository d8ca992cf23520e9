// Adds one A-Series robot, built from an ASeriesMorphology, to a physics::PhysicsDescription: its bodies with
// their geoms and boards, its 21 motorised hinges and 2 fixed joints, and its contact exclusions. The decisions
// taken on the original's quirks (lifted anchors, lumped masses, the penetrable pelvis, board × PDA) are in
// docs/aseries-morphology.md.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "model/aseries/aseries_morphology.h"
#include "model/physics/physics_description.h"

namespace orcs::aseries {

/// Where one robot goes and what it is called.
struct ASeriesPlacement {
  /// Agent name; prefixes every body and joint name ("Humanoid/Right/Foot"). Non-empty.
  std::string agent_name = "Humanoid";
  /// Added to every body position and anchor after the rotation (the model's Position, §1), m.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// Rotation of the whole robot about the world origin, applied before `position` (the model's Orientation).
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// One accelerometer board as the sensors need it.
struct ASeriesBoardLayout {
  std::string name;         ///< board name, e.g. "ABFR"; also the name of its geom in the host body
  int host_body = -1;       ///< index of the host body in PhysicsDescription::bodies
  int geom_in_body = -1;    ///< position of the board's geom in the host body's geoms
  Eigen::Vector3d local_position = Eigen::Vector3d::Zero();  ///< board centre in the host body frame, m
  Eigen::Quaterniond local_rotation = Eigen::Quaterniond::Identity();  ///< board frame relative to host frame
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitZ();  ///< AccelAxis1 after the local rotation, host frame, unit
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitX();  ///< AccelAxis2 after the local rotation, host frame, unit
};

/// Where AddASeries put one robot in the description: indices, in the morphology's orders.
struct ASeriesLayout {
  std::string agent_name;        ///< the placement's agent name
  std::vector<int> bodies;       ///< PhysicsDescription body index of each morphology body, body order
  std::vector<int> motors;       ///< PhysicsDescription joint index of each motorised hinge, motor order
  std::vector<int> fixed_joints;  ///< PhysicsDescription joint index of each fixed joint, morphology order
  std::vector<ASeriesBoardLayout> boards;  ///< the accelerometer boards, board order (ABFR … ABAL)
};

/// Appends one robot to `description` and returns where it went. Body "<agent>/<body>": geoms[0] is the main
/// box carrying the box mass (collides = false for a penetrable body), then the extra geoms and the boards
/// (named after the board) with their masses, so the compiled body mass is the original's §2b total. Joint
/// "<agent>/<motor>": a limited, motorised hinge, anchors lifted by `morphology.lift` (quirk 1); then the fixed
/// joints "<agent>/<name>". Contact exclusions are appended as body pairs; an entry naming one geom (board ×
/// PDA, #4/#5) is not applied, since the physics layer excludes whole bodies only (see the docs).
/// Throws InputError for an empty agent name, a non-finite placement or a morphology naming unknown bodies.
ASeriesLayout AddASeries(const ASeriesMorphology& morphology, const ASeriesPlacement& placement,
                         physics::PhysicsDescription& description);

}  // namespace orcs::aseries
