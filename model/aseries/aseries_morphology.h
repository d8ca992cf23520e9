// The A-Series morphology as data (description layer): bodies, extra geoms, accelerometer boards, joints and
// the collision-suppression list, exactly as spec/aseries.md §2–§5 gives them. The numbers live in
// aseries_morphology.json, which the build embeds into the binary, so a worker needs no file at run time.
// AddASeries (aseries_builder.h) turns a morphology into physics bodies and joints.
//
// Units as in the JSON: metres, kilograms, degrees. Frame: the ORCS world frame, +Y up, +Z forward, robot's
// right = −X, initial pose = T-pose with every joint angle 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::aseries {

/// A colour, red, green, blue, alpha, each 0…255. Visual only.
using Rgba = std::array<int, 4>;

/// One rigid body: a box (its main geom).
struct MorphologyBody {
  std::string name;  ///< NERD name without the agent, e.g. "Right/Foot"
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    ///< W × H × D: box edge lengths along body x, y, z, m
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< world centre in the initial pose, lift included, m
  double mass = 0.0;     ///< mass of the main box alone, kg (extra geoms and boards add theirs, §2b)
  std::string material;  ///< physics material of the main box (MaterialTable name), e.g. "ABS"
  Rgba color{};          ///< display colour of the main box
  std::string texture;   ///< display texture, visual only; "" for none
  bool penetrable = false;  ///< true: the main box collides with nothing (the pelvis box); extra geoms still do
  /// Principal moments of inertia about the body centre along the body's x, y, z, kg·m²; zero = NERD's rule (a
  /// uniform box of the main box's size carrying the body's whole mass, §2b).
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();
};

/// Why `inertia` (principal moments, kg·m²) cannot be a body's: "" when it can — all zero (the mass rule), or all
/// positive with each at most the sum of the other two, as a rigid body's are.
std::string InertiaProblem(const Eigen::Vector3d& inertia);

/// An extra collision box rigidly attached to a host body (§3a), axis-aligned in the host frame.
struct MorphologyGeom {
  std::string host;  ///< name of the host body (MorphologyBody::name)
  std::string name;  ///< unique within the host, e.g. "Right sole pad heel"
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    ///< box edge lengths along host x, y, z, m
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< centre relative to the host body centre, host frame, m
  double mass = 0.0;     ///< kg added to the host body (it does not move the host's COM, §2b)
  std::string material;  ///< physics material (MaterialTable name)
  Rgba color{};          ///< display colour
  std::string texture;   ///< display texture, visual only; "" for none
};

/// An ADXL213 accelerometer board (§5): a collision box of its host body that also carries a 2-axis sensor.
struct MorphologyBoard {
  std::string name;  ///< board name, e.g. "ABFR" (the left upper-body board really is "ABML", quirk 14)
  std::string host;  ///< name of the host body
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< board centre relative to the host centre, host frame, m
  /// Board frame relative to the host frame as NERD's Euler triple (α, β, γ), degrees, R = Rz(γ)·Ry(β)·Rx(α).
  Eigen::Vector3d rotation_degrees = Eigen::Vector3d::Zero();
  /// The same rotation as a unit quaternion (derived from rotation_degrees when parsed).
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< box edge lengths along the board frame's x, y, z, m
  double mass = 0.0;                               ///< kg added to the host body
  std::string material;                            ///< physics material (MaterialTable name)
  Rgba color{};                                    ///< display colour
  std::string texture;                             ///< display texture, visual only; "" for none
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitZ();  ///< sensing axis 1 (AccelAxis1), board frame, unit
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitX();  ///< sensing axis 2 (AccelAxis2), board frame, unit
};

/// A motorised hinge (§4c). ODE body 1 = first_body, body 2 = second_body.
struct MorphologyMotor {
  std::string name;         ///< motor name, e.g. "Right/Knee"
  std::string first_body;   ///< NERD's FirstBody (ODE body 1)
  std::string second_body;  ///< NERD's SecondBody (ODE body 2); "" = the static world (rigs only)
  /// AxisPoint1: the anchor, world, initial pose, m — UNLIFTED, as NERD passes it to ODE (§1, quirk 1).
  Eigen::Vector3d axis_point1 = Eigen::Vector3d::Zero();
  /// AxisPoint2, world, unlifted, m; the hinge axis is unit(axis_point2 − axis_point1).
  Eigen::Vector3d axis_point2 = Eigen::Vector3d::Zero();
  double min_degrees = 0.0;  ///< lower hinge stop relative to the initial pose, degrees
  double max_degrees = 0.0;  ///< upper hinge stop, degrees
};

/// A fixed joint welding two bodies in their initial relative pose (§4b).
struct MorphologyFixedJoint {
  std::string name;         ///< e.g. "Middle/PDAConnector"
  std::string first_body;   ///< body 1
  std::string second_body;  ///< body 2
};

/// One entry of the original's collision-suppression list (§3b): contacts between these are not created.
struct MorphologyExclusion {
  std::string first;       ///< a body name
  /// "" = every geom of `first`; else the name of one geom or board of `first` (entries #4/#5: ABAR, ABAL).
  std::string first_geom;
  std::string second;      ///< a body name (every geom of it)
};

/// The whole morphology.
struct ASeriesMorphology {
  /// The global lift NERD applies to every body after building, m (§1): already included in
  /// MorphologyBody::centre, NOT in the motor anchors.
  double lift = 0.0;
  /// The body the kinematic tree hangs from when nothing holds the robot (spec §4a: the pelvis,
  /// "Middle/InvisiblePart"): posing the joints (Simulation::SetAgentJointAngles) leaves it where it is and turns
  /// the limbs away from it. A body name of `bodies`; "" only when no body exists (never for a parsed file).
  std::string root_body;
  std::vector<MorphologyBody> bodies;             ///< in NERD's creation order (the agent's object order)
  std::vector<MorphologyGeom> geoms;              ///< extra geoms, in NERD's order
  std::vector<MorphologyBoard> boards;            ///< accelerometer boards in output order (ABFR … ABAL)
  std::vector<MorphologyMotor> motors;            ///< motorised hinges in motor order (= agent I/O order)
  std::vector<MorphologyFixedJoint> fixed_joints;  ///< fixed joints
  std::vector<MorphologyExclusion> contact_exclusions;  ///< the suppression list, NERD's order

  /// Index of a body by name, or -1.
  int FindBody(std::string_view name) const;
  /// Index of a motor by name, or -1.
  int FindMotor(std::string_view name) const;
  /// Index of a board by name, or -1.
  int FindBoard(std::string_view name) const;
};

/// Parses and checks a morphology JSON document. `source` names it in error messages (a file name).
/// Throws InputError naming the field path ("bodies[3].mass") and what was expected and found: for malformed
/// JSON, a missing, unknown or wrongly typed field, a non-positive size or mass, an unknown material, a
/// duplicate name, a reference to an unknown body or geom, a zero axis, a non-unit sensing axis or min > max.
/// Objects may carry a "comment" member, which is ignored.
ASeriesMorphology ParseASeriesMorphology(const std::string& json, const std::string& source);

/// A morphology as a robot file (the format ParseASeriesMorphology reads; docs/formats.md, "Robot files"), with
/// `comment` lines as its "comment": what `orcs-sim --export-robot` writes. Parsing the text gives `morphology` back.
std::string WriteASeriesMorphology(const ASeriesMorphology& morphology, const std::vector<std::string>& comment = {});

/// The morphology embedded in the binary at build time (model/aseries/aseries_morphology.json), parsed once.
const ASeriesMorphology& DefaultASeriesMorphology();

/// The embedded JSON text itself.
std::string_view DefaultASeriesMorphologyJson();

}  // namespace orcs::aseries
