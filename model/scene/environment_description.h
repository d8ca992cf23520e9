// An ORCS XML environment (format v1.0), as read: passive objects and agents. Editable description layer;
// WorldModel compiles it. Units as in the file: metres, kilograms, Euler angles in degrees.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "model/aseries/aseries_morphology.h"
#include "model/core/value.h"

namespace orcs::scene {

enum class ObjectType { kBox, kSphere };

/// One <object> of the <Environment>.
struct ObjectDescription {
  std::string name;              ///< unique name; its values live under /Sim/<name>/
  ObjectType type = ObjectType::kBox;  ///< collision shape
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     ///< centre, world, m
  Eigen::Vector3d orientation = Eigen::Vector3d::Zero();  ///< Euler angles (α, β, γ), degrees (R = Rz·Ry·Rx)
  Eigen::Vector3d dimension = Eigen::Vector3d::Zero();    ///< box: width x, height y, depth z, m; sphere: (radius, 0, 0)
  std::string material = "Default";  ///< material name (physics::MaterialTable)
  Color color{255, 255, 255, 255};   ///< display colour (visual only)
  std::string texture;               ///< texture name (visual only)
  bool dynamic = false;              ///< true: moves under gravity and contacts; needs a mass
  double mass = 0.0;                 ///< kg; > 0 when dynamic
  int line = 0;                      ///< line in the source file, for messages
};

/// One agent of the <Agent> section: an <ASeries> robot or a <Pendulum> rig (docs/formats.md).
struct AgentDescription {
  std::string type = "ASeries";  ///< robot model: "ASeries" or "Pendulum"
  std::string name = "Humanoid";  ///< agent name, the prefix of its values (/Sim/<name>/...)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     ///< model placement, m
  Eigen::Vector3d orientation = Eigen::Vector3d::Zero();  ///< model rotation, Euler degrees
  /// ASeries: a body welded to the world (a test stand holding the robot), e.g. "Middle/UpperBody"; "" = none
  std::string hold_body;
  /// ASeries: the robot's morphology read from a robot file (docs/formats.md, "Robot files"); null = the built-in
  /// A-Series. Shared and immutable, so descriptions copy cheaply.
  std::shared_ptr<const aseries::ASeriesMorphology> morphology;
  std::string morphology_source;  ///< ASeries: the robot file's name, "" for the built-in A-Series
  double pole_mass = 0.5;     ///< Pendulum: kg
  double pole_length = 0.3;   ///< Pendulum: m, axis to tip
  int line = 0;                  ///< line in the source file, for messages
};

struct EnvironmentDescription {
  std::string source;  ///< file name (or "<inline>") it was read from
  std::vector<ObjectDescription> objects;  ///< in file order
  std::vector<AgentDescription> agents;    ///< in file order
  std::string floor_material = "PVC";      ///< material of the floor plane y = 0 (the original's Prototypes/Ground)
};

}  // namespace orcs::scene
