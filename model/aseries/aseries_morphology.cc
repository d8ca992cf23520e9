#include "model/aseries/aseries_morphology.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <set>
#include <string>
#include <utility>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/rotation.h"
#include "model/physics/material_table.h"

namespace orcs::aseries {

std::string InertiaProblem(const Eigen::Vector3d& inertia) {
  if (inertia.isZero(0.0)) return "";
  const bool positive = inertia.minCoeff() > 0.0 && inertia.allFinite();
  const bool triangle = inertia.x() <= inertia.y() + inertia.z() && inertia.y() <= inertia.x() + inertia.z() &&
                        inertia.z() <= inertia.x() + inertia.y();
  if (positive && triangle) return "";
  return "all zero (the mass rule), or three positive moments in kg·m², each at most the sum of the other two";
}

// Defined in the file CMake generates from aseries_morphology.json.
namespace internal {
extern const char kASeriesMorphologyJson[];
}  // namespace internal

namespace {

using Json = nlohmann::json;

constexpr std::string_view kFormat = "orcs-aseries-morphology";
constexpr int kVersion = 1;
// Sensing axes are given as exact unit vectors; anything further off is a typo.
constexpr double kUnitTolerance = 1e-9;

std::string Num(double value) {
  std::array<char, 32> text{};
  const auto result = std::to_chars(text.data(), text.data() + text.size(), value);
  return std::string(text.data(), result.ptr);
}

std::string Vec(const Eigen::Vector3d& v) { return "[" + Num(v.x()) + ", " + Num(v.y()) + ", " + Num(v.z()) + "]"; }

using Node = JsonNode;

Rgba ColorOf(const Node& node) {
  const std::string expected = "an array of 4 integers 0..255 (red, green, blue, alpha)";
  if (!node.value().is_array() || node.value().size() != 4) node.Fail(expected);
  Rgba rgba{};
  const std::vector<Node> elements = node.Elements();
  for (std::size_t i = 0; i < 4; ++i) {
    const Json& element = elements[i].value();
    if (!element.is_number_integer() || element.get<long long>() < 0 || element.get<long long>() > 255) {
      elements[i].Fail("an integer 0..255");
    }
    rgba[i] = element.get<int>();
  }
  return rgba;
}

double PositiveNumber(const Node& node, const std::string& what) {
  const double value = node.Number("a positive number (" + what + ")");
  if (!(value > 0.0)) node.Fail("a positive number (" + what + ")", Num(value));
  return value;
}

double NonNegativeNumber(const Node& node, const std::string& what) {
  const double value = node.Number("a non-negative number (" + what + ")");
  if (value < 0.0) node.Fail("a non-negative number (" + what + ")", Num(value));
  return value;
}

Eigen::Vector3d Size(const Node& node) {
  const Eigen::Vector3d size = node.Vector3("box edge lengths x, y, z in m");
  if (!(size.minCoeff() > 0.0)) node.Fail("three positive edge lengths (m)", Vec(size));
  return size;
}

std::string NonEmptyString(const Node& node, const std::string& what) {
  const std::string text = node.String("a non-empty string (" + what + ")");
  if (text.empty()) node.Fail("a non-empty string (" + what + ")", "\"\"");
  return text;
}

// The robot must never fall back to the unknown-material rule: a misspelt material is an error.
std::string Material(const Node& node) {
  const std::string name = node.String("a material name");
  if (physics::MaterialTable::IndexOf(name) == physics::MaterialTable::kUnknown) {
    node.Fail("a known material (PlasticsWhite, PlasticsGray, ABS, Latex, PVC, Wood, Carpet, Default, Light, "
              "Custom1, Custom2)",
              "\"" + name + "\"");
  }
  return name;
}

Eigen::Vector3d UnitAxis(const Node& node) {
  const Eigen::Vector3d axis = node.Vector3("a unit vector");
  if (std::abs(axis.norm() - 1.0) > kUnitTolerance) node.Fail("a unit vector", Vec(axis));
  return axis;
}

// A reference to a body by name.
std::string BodyRef(const Node& node, const ASeriesMorphology& morphology) {
  const std::string name = node.String("a body name");
  if (morphology.FindBody(name) < 0) node.Fail("the name of a body in 'bodies'", "unknown body \"" + name + "\"");
  return name;
}

MorphologyBody ParseBody(const Node& node) {
  node.ExpectOnly({"name", "size", "centre", "mass", "material", "color", "texture", "penetrable", "inertia"});
  MorphologyBody body;
  body.name = NonEmptyString(node.At("name"), "body name");
  body.size = Size(node.At("size"));
  body.centre = node.At("centre").Vector3("world centre in m");
  body.mass = PositiveNumber(node.At("mass"), "box mass in kg");
  body.material = Material(node.At("material"));
  body.color = ColorOf(node.At("color"));
  body.texture = node.At("texture").String("a texture name or \"\"");
  body.penetrable = node.At("penetrable").Bool("true or false");
  if (node.Has("inertia")) {
    const Node inertia = node.At("inertia");
    body.inertia = inertia.Vector3("principal moments of inertia in kg·m²");
    if (const std::string problem = InertiaProblem(body.inertia); !problem.empty()) inertia.Fail(problem, Vec(body.inertia));
  }
  return body;
}

MorphologyGeom ParseGeom(const Node& node, const ASeriesMorphology& morphology) {
  node.ExpectOnly({"host", "name", "size", "offset", "mass", "material", "color", "texture"});
  MorphologyGeom geom;
  geom.host = BodyRef(node.At("host"), morphology);
  geom.name = NonEmptyString(node.At("name"), "geom name");
  geom.size = Size(node.At("size"));
  geom.offset = node.At("offset").Vector3("offset from the host centre in m");
  geom.mass = NonNegativeNumber(node.At("mass"), "mass in kg");
  geom.material = Material(node.At("material"));
  geom.color = ColorOf(node.At("color"));
  geom.texture = node.At("texture").String("a texture name or \"\"");
  return geom;
}

MorphologyBoard ParseBoard(const Node& node, const ASeriesMorphology& morphology) {
  node.ExpectOnly({"name", "host", "position", "rotation_degrees", "size", "mass", "material", "color", "texture",
                   "axis1", "axis2"});
  MorphologyBoard board;
  board.name = NonEmptyString(node.At("name"), "board name");
  board.host = BodyRef(node.At("host"), morphology);
  board.position = node.At("position").Vector3("position in the host frame in m");
  board.rotation_degrees = node.At("rotation_degrees").Vector3("NERD Euler angles in degrees");
  board.rotation = QuaternionFromEulerDegrees(board.rotation_degrees);
  board.size = Size(node.At("size"));
  board.mass = NonNegativeNumber(node.At("mass"), "mass in kg");
  board.material = Material(node.At("material"));
  board.color = ColorOf(node.At("color"));
  board.texture = node.At("texture").String("a texture name or \"\"");
  board.axis1 = UnitAxis(node.At("axis1"));
  board.axis2 = UnitAxis(node.At("axis2"));
  return board;
}

// Two distinct dynamic bodies of the morphology.
void ParseBodyPair(const Node& node, const ASeriesMorphology& morphology, std::string& first, std::string& second) {
  first = BodyRef(node.At("first_body"), morphology);
  second = BodyRef(node.At("second_body"), morphology);
  if (first == second) node.At("second_body").Fail("a body other than first_body", "\"" + second + "\" again");
}

MorphologyMotor ParseMotor(const Node& node, const ASeriesMorphology& morphology) {
  node.ExpectOnly({"name", "first_body", "second_body", "axis_point1", "axis_point2", "min_degrees", "max_degrees"});
  MorphologyMotor motor;
  motor.name = NonEmptyString(node.At("name"), "motor name");
  ParseBodyPair(node, morphology, motor.first_body, motor.second_body);
  motor.axis_point1 = node.At("axis_point1").Vector3("anchor in m");
  motor.axis_point2 = node.At("axis_point2").Vector3("second axis point in m");
  if ((motor.axis_point2 - motor.axis_point1).norm() < 1e-9) {
    node.At("axis_point2").Fail("a point other than axis_point1 (they define the axis)", Vec(motor.axis_point2));
  }
  // ODE's hinge stops work within ±180°.
  const std::string range = "an angle within -180..180 degrees";
  motor.min_degrees = node.At("min_degrees").Number(range);
  motor.max_degrees = node.At("max_degrees").Number(range);
  if (std::abs(motor.min_degrees) > 180.0) node.At("min_degrees").Fail(range, Num(motor.min_degrees));
  if (std::abs(motor.max_degrees) > 180.0) node.At("max_degrees").Fail(range, Num(motor.max_degrees));
  if (motor.min_degrees > motor.max_degrees) {
    node.At("min_degrees").Fail("min_degrees <= max_degrees (" + Num(motor.max_degrees) + ")", Num(motor.min_degrees));
  }
  return motor;
}

MorphologyFixedJoint ParseFixedJoint(const Node& node, const ASeriesMorphology& morphology) {
  node.ExpectOnly({"name", "first_body", "second_body"});
  MorphologyFixedJoint joint;
  joint.name = NonEmptyString(node.At("name"), "joint name");
  ParseBodyPair(node, morphology, joint.first_body, joint.second_body);
  return joint;
}

bool BodyHasGeom(const ASeriesMorphology& morphology, const std::string& body, const std::string& geom) {
  const bool in_geoms = std::any_of(morphology.geoms.begin(), morphology.geoms.end(),
                                    [&](const MorphologyGeom& g) { return g.host == body && g.name == geom; });
  const bool in_boards = std::any_of(morphology.boards.begin(), morphology.boards.end(),
                                     [&](const MorphologyBoard& b) { return b.host == body && b.name == geom; });
  return in_geoms || in_boards;
}

MorphologyExclusion ParseExclusion(const Node& node, const ASeriesMorphology& morphology) {
  node.ExpectOnly({"first", "first_geom", "second"});
  MorphologyExclusion exclusion;
  exclusion.first = BodyRef(node.At("first"), morphology);
  exclusion.second = BodyRef(node.At("second"), morphology);
  if (node.Has("first_geom")) {
    const Node geom = node.At("first_geom");
    exclusion.first_geom = geom.String("the name of a geom or board of the first body");
    if (!exclusion.first_geom.empty() && !BodyHasGeom(morphology, exclusion.first, exclusion.first_geom)) {
      geom.Fail("the name of a geom or board of body \"" + exclusion.first + "\"",
                "\"" + exclusion.first_geom + "\"");
    }
  }
  return exclusion;
}

// Names that must be unique within a list (bodies, motors, ...): `key` gives the name of the i-th element.
template <typename T, typename Key>
void CheckUnique(const std::vector<T>& items, const Node& list, Key key, const std::string& what) {
  std::set<std::string> seen;
  const std::vector<Node> nodes = list.Elements();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string name = key(items[i]);
    if (!seen.insert(name).second) nodes[i].Fail(what + " unique in the list", "\"" + name + "\" used twice");
  }
}


}  // namespace

int ASeriesMorphology::FindBody(std::string_view name) const {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int ASeriesMorphology::FindMotor(std::string_view name) const {
  for (std::size_t i = 0; i < motors.size(); ++i) {
    if (motors[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int ASeriesMorphology::FindBoard(std::string_view name) const {
  for (std::size_t i = 0; i < boards.size(); ++i) {
    if (boards[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

namespace {

void CheckFormatAndVersion(const Node& root) {
  const Node format = root.At("format");
  if (format.String("\"" + std::string(kFormat) + "\"") != kFormat) {
    format.Fail("\"" + std::string(kFormat) + "\"", "\"" + format.String("a string") + "\"");
  }
  const Node version = root.At("version");
  if (version.Integer("the integer " + std::to_string(kVersion)) != kVersion) {
    version.Fail("version " + std::to_string(kVersion), std::to_string(version.Integer("an integer")));
  }
}

// Geom and board names share one namespace per host body (they become geoms of one physics body).
void CheckGeomNamesPerHost(const ASeriesMorphology& morphology, const Node& geoms, const Node& boards) {
  std::set<std::pair<std::string, std::string>> seen;
  const std::vector<Node> geom_nodes = geoms.Elements();
  for (std::size_t i = 0; i < morphology.geoms.size(); ++i) {
    const MorphologyGeom& g = morphology.geoms[i];
    if (!seen.emplace(g.host, g.name).second) {
      geom_nodes[i].At("name").Fail("a name unique within its host body", "\"" + g.name + "\" used twice");
    }
  }
  const std::vector<Node> board_nodes = boards.Elements();
  for (std::size_t i = 0; i < morphology.boards.size(); ++i) {
    const MorphologyBoard& b = morphology.boards[i];
    if (!seen.emplace(b.host, b.name).second) {
      board_nodes[i].At("name").Fail("a name unique among the geoms of its host body", "\"" + b.name + "\"");
    }
  }
}

// Motors and fixed joints become joints of one world: one namespace.
void CheckJointNames(const ASeriesMorphology& morphology, const Node& motors, const Node& fixed) {
  std::set<std::string> seen;
  auto check = [&seen](const std::string& name, const Node& node) {
    if (!seen.insert(name).second) {
      node.At("name").Fail("a joint name unique among motors and fixed joints", "\"" + name + "\" used twice");
    }
  };
  const std::vector<Node> motor_nodes = motors.Elements();
  for (std::size_t i = 0; i < morphology.motors.size(); ++i) check(morphology.motors[i].name, motor_nodes[i]);
  const std::vector<Node> fixed_nodes = fixed.Elements();
  for (std::size_t i = 0; i < morphology.fixed_joints.size(); ++i) {
    check(morphology.fixed_joints[i].name, fixed_nodes[i]);
  }
}

void ParseBodies(const Node& root, ASeriesMorphology& morphology) {
  const Node bodies = root.At("bodies");
  for (const Node& node : bodies.Elements()) morphology.bodies.push_back(ParseBody(node));
  CheckUnique(morphology.bodies, bodies, [](const MorphologyBody& b) { return b.name; }, "a body name");
  // Optional: the first body when absent.
  if (root.Has("root_body")) {
    morphology.root_body = BodyRef(root.At("root_body"), morphology);
  } else if (!morphology.bodies.empty()) {
    morphology.root_body = morphology.bodies.front().name;
  }
}

void ParseGeomsAndBoards(const Node& root, ASeriesMorphology& morphology) {
  const Node geoms = root.At("geoms");
  for (const Node& node : geoms.Elements()) morphology.geoms.push_back(ParseGeom(node, morphology));
  const Node boards = root.At("boards");
  for (const Node& node : boards.Elements()) morphology.boards.push_back(ParseBoard(node, morphology));
  CheckUnique(morphology.boards, boards, [](const MorphologyBoard& b) { return b.name; }, "a board name");
  CheckGeomNamesPerHost(morphology, geoms, boards);
}

void ParseJoints(const Node& root, ASeriesMorphology& morphology) {
  const Node motors = root.At("motors");
  for (const Node& node : motors.Elements()) morphology.motors.push_back(ParseMotor(node, morphology));
  const Node fixed = root.At("fixed_joints");
  for (const Node& node : fixed.Elements()) morphology.fixed_joints.push_back(ParseFixedJoint(node, morphology));
  CheckJointNames(morphology, motors, fixed);
}

}  // namespace

ASeriesMorphology ParseASeriesMorphology(const std::string& json, const std::string& source) {
  const Json document = ParseJson(json, source);
  const Node root(document, "", source);
  root.ExpectOnly({"format", "version", "lift", "root_body", "bodies", "geoms", "boards", "motors", "fixed_joints",
                   "contact_exclusions"});
  CheckFormatAndVersion(root);
  ASeriesMorphology morphology;
  morphology.lift = NonNegativeNumber(root.At("lift"), "lift in m");
  ParseBodies(root, morphology);
  ParseGeomsAndBoards(root, morphology);
  ParseJoints(root, morphology);
  for (const Node& node : root.At("contact_exclusions").Elements()) {
    morphology.contact_exclusions.push_back(ParseExclusion(node, morphology));
  }
  return morphology;
}

std::string_view DefaultASeriesMorphologyJson() { return internal::kASeriesMorphologyJson; }

const ASeriesMorphology& DefaultASeriesMorphology() {
  static const ASeriesMorphology morphology =
      ParseASeriesMorphology(std::string(DefaultASeriesMorphologyJson()), "model/aseries/aseries_morphology.json");
  return morphology;
}

}  // namespace orcs::aseries

namespace orcs::aseries {
namespace {

nlohmann::ordered_json Vector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::string WriteASeriesMorphology(const ASeriesMorphology& morphology, const std::vector<std::string>& comment) {
  nlohmann::ordered_json out = {{"format", "orcs-aseries-morphology"}, {"version", 1}};
  if (!comment.empty()) out["comment"] = comment;
  out["lift"] = morphology.lift;
  out["root_body"] = morphology.root_body;
  out["bodies"] = nlohmann::ordered_json::array();
  for (const MorphologyBody& b : morphology.bodies) {
    out["bodies"].push_back({{"name", b.name}, {"size", Vector(b.size)}, {"centre", Vector(b.centre)},
                             {"mass", b.mass}, {"material", b.material}, {"color", b.color},
                             {"texture", b.texture}, {"penetrable", b.penetrable}});
    if (!b.inertia.isZero(0.0)) out["bodies"].back()["inertia"] = Vector(b.inertia);
  }
  out["geoms"] = nlohmann::ordered_json::array();
  for (const MorphologyGeom& g : morphology.geoms) {
    out["geoms"].push_back({{"host", g.host}, {"name", g.name}, {"size", Vector(g.size)}, {"offset", Vector(g.offset)},
                            {"mass", g.mass}, {"material", g.material}, {"color", g.color}, {"texture", g.texture}});
  }
  out["boards"] = nlohmann::ordered_json::array();
  for (const MorphologyBoard& b : morphology.boards) {
    out["boards"].push_back({{"name", b.name}, {"host", b.host}, {"position", Vector(b.position)},
                             {"rotation_degrees", Vector(b.rotation_degrees)}, {"size", Vector(b.size)},
                             {"mass", b.mass}, {"material", b.material}, {"color", b.color}, {"texture", b.texture},
                             {"axis1", Vector(b.axis1)}, {"axis2", Vector(b.axis2)}});
  }
  out["motors"] = nlohmann::ordered_json::array();
  for (const MorphologyMotor& m : morphology.motors) {
    out["motors"].push_back({{"name", m.name}, {"first_body", m.first_body}, {"second_body", m.second_body},
                             {"axis_point1", Vector(m.axis_point1)}, {"axis_point2", Vector(m.axis_point2)},
                             {"min_degrees", m.min_degrees}, {"max_degrees", m.max_degrees}});
  }
  out["fixed_joints"] = nlohmann::ordered_json::array();
  for (const MorphologyFixedJoint& f : morphology.fixed_joints) {
    out["fixed_joints"].push_back({{"name", f.name}, {"first_body", f.first_body}, {"second_body", f.second_body}});
  }
  out["contact_exclusions"] = nlohmann::ordered_json::array();
  for (const MorphologyExclusion& e : morphology.contact_exclusions) {
    nlohmann::ordered_json entry = {{"first", e.first}};
    if (!e.first_geom.empty()) entry["first_geom"] = e.first_geom;
    entry["second"] = e.second;
    out["contact_exclusions"].push_back(std::move(entry));
  }
  return out.dump(2) + "\n";
}

}  // namespace orcs::aseries
