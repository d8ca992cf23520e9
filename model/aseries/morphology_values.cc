#include "model/aseries/morphology_values.h"

#include <cctype>
#include <functional>

#include "model/core/error.h"
#include "model/core/rotation.h"
#include "model/core/text.h"
#include "model/physics/material_table.h"

namespace orcs::aseries {
namespace {

// What a box of the robot can be: the physics must be able to build it (a zero mass or size cannot be).
constexpr double kMinMass = 1e-6;  // kg
constexpr double kMaxMass = 1e3;   // kg
constexpr double kMinSize = 1e-5;  // m
constexpr double kMaxSize = 10.0;  // m
constexpr double kMaxStop = 360.0;  // degrees either way
constexpr double kMinAxisLength = 1e-6;  // m between a hinge's two axis points: less has no direction

constexpr const char* kSizeNames[3] = {"Width", "Height", "Depth"};

// The settable parts of one box, main or extra: pointers into a morphology being read or written. `inertia` is
// a main box's only (null for extra geoms and boards, whose mass joins their host's).
struct BoxFields {
  double* mass;
  Eigen::Vector3d* size;
  std::string* material;
  Rgba* color;
  Eigen::Vector3d* inertia = nullptr;
};

std::vector<std::string> MaterialNames() {
  std::vector<std::string> names;
  for (int i = 0; i < physics::MaterialTable::kCount; ++i) names.emplace_back(physics::MaterialTable::NameOf(i));
  return names;
}

Color ToColor(const Rgba& rgba) { return {rgba[0], rgba[1], rgba[2], rgba[3]}; }
Rgba ToRgba(const Color& color) { return {color.r, color.g, color.b, color.a}; }

// Calls `box(prefix, fields)` for every main box, extra geom and accelerometer board, `board(prefix, board)` for
// every board's placement, and `hinge(prefix, motor)` for every motor, in the morphology's order; prefix is the
// path up to the value name ("/Sim/Humanoid/Right/Foot/", "/Sim/Humanoid/ABFR/").
void ForEachPart(ASeriesMorphology& morphology, const std::string& agent,
                 const std::function<void(const std::string&, BoxFields)>& box,
                 const std::function<void(const std::string&, MorphologyBoard&)>& board,
                 const std::function<void(const std::string&, MorphologyMotor&)>& hinge) {
  const std::string root = "/Sim/" + agent + "/";
  for (MorphologyBody& body : morphology.bodies) {
    box(root + body.name + "/", {&body.mass, &body.size, &body.material, &body.color, &body.inertia});
  }
  for (MorphologyGeom& geom : morphology.geoms) {
    box(root + geom.host + "/" + GeomValueName(geom.name) + "/", {&geom.mass, &geom.size, &geom.material, &geom.color, nullptr});
  }
  for (MorphologyBoard& b : morphology.boards) {
    box(root + b.name + "/", {&b.mass, &b.size, &b.material, &b.color, nullptr});
    board(root + b.name + "/", b);
  }
  for (MorphologyMotor& motor : morphology.motors) hinge(root + motor.name + "/", motor);
}

}  // namespace

std::string GeomValueName(const std::string& geom_name) {
  std::string name;
  bool word_start = true;
  for (const char c : geom_name) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0) {
      word_start = true;
      continue;
    }
    name += word_start ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    word_start = false;
  }
  return name;
}

void AddMorphologyValues(const ASeriesMorphology& morphology, const std::string& agent, VariableRepository& values) {
  ASeriesMorphology copy = morphology;  // ForEachPart walks a mutable morphology; nothing is written to it here
  const std::vector<std::string> materials = MaterialNames();
  ForEachPart(
      copy, agent,
      [&](const std::string& prefix, BoxFields box) {
        values.Add(prefix + "Mass", *box.mass).SetRange(kMinMass, kMaxMass);
        for (int axis = 0; axis < 3; ++axis) {
          values.Add(prefix + kSizeNames[axis], (*box.size)[axis]).SetRange(kMinSize, kMaxSize);
        }
        values.Add(prefix + "Material", *box.material).SetChoices(materials);
        values.Add(prefix + "Color", ToColor(*box.color));
        if (box.inertia != nullptr) values.Add(prefix + "Inertia", *box.inertia);
      },
      [&](const std::string& prefix, MorphologyBoard& board) {
        values.Add(prefix + "Position", board.position);
        values.Add(prefix + "Rotation", board.rotation_degrees);
      },
      [&](const std::string& prefix, MorphologyMotor& motor) {
        values.Add(prefix + "MinAngle", motor.min_degrees).SetRange(-kMaxStop, kMaxStop);
        values.Add(prefix + "MaxAngle", motor.max_degrees).SetRange(-kMaxStop, kMaxStop);
        values.Add(prefix + "AxisPoint1", motor.axis_point1);
        values.Add(prefix + "AxisPoint2", motor.axis_point2);
      });
}

std::vector<std::string> MorphologyValuePaths(const ASeriesMorphology& morphology, const std::string& agent) {
  ASeriesMorphology copy = morphology;
  std::vector<std::string> paths;
  ForEachPart(
      copy, agent,
      [&](const std::string& prefix, BoxFields box) {
        for (const char* name : {"Mass", "Width", "Height", "Depth", "Material", "Color"}) paths.push_back(prefix + name);
        if (box.inertia != nullptr) paths.push_back(prefix + "Inertia");
      },
      [&](const std::string& prefix, MorphologyBoard&) {
        for (const char* name : {"Position", "Rotation"}) paths.push_back(prefix + name);
      },
      [&](const std::string& prefix, MorphologyMotor&) {
        for (const char* name : {"MinAngle", "MaxAngle", "AxisPoint1", "AxisPoint2"}) paths.push_back(prefix + name);
      });
  return paths;
}

ASeriesMorphology ApplyMorphologyValues(const ASeriesMorphology& morphology, const std::string& agent,
                                        const VariableRepository& values) {
  ASeriesMorphology applied = morphology;
  ForEachPart(
      applied, agent,
      [&](const std::string& prefix, BoxFields box) {
        *box.mass = values.Get(prefix + "Mass").as_double();
        for (int axis = 0; axis < 3; ++axis) (*box.size)[axis] = values.Get(prefix + kSizeNames[axis]).as_double();
        *box.material = values.Get(prefix + "Material").as_string();
        *box.color = ToRgba(values.Get(prefix + "Color").as_color());
        if (box.inertia != nullptr) {
          *box.inertia = values.Get(prefix + "Inertia").as_vector3();
          if (const std::string problem = InertiaProblem(*box.inertia); !problem.empty()) {
            throw InputError(prefix + "Inertia", 0, "expected " + problem + ", found " + Value(*box.inertia).ToString());
          }
        }
      },
      [&](const std::string& prefix, MorphologyBoard& board) {
        board.position = values.Get(prefix + "Position").as_vector3();
        board.rotation_degrees = values.Get(prefix + "Rotation").as_vector3();
        board.rotation = QuaternionFromEulerDegrees(board.rotation_degrees);
      },
      [&](const std::string& prefix, MorphologyMotor& motor) {
        motor.min_degrees = values.Get(prefix + "MinAngle").as_double();
        motor.max_degrees = values.Get(prefix + "MaxAngle").as_double();
        motor.axis_point1 = values.Get(prefix + "AxisPoint1").as_vector3();
        motor.axis_point2 = values.Get(prefix + "AxisPoint2").as_vector3();
        if ((motor.axis_point2 - motor.axis_point1).norm() < kMinAxisLength) {
          throw InputError(prefix + "AxisPoint2", 0,
                           "expected a point other than " + prefix + "AxisPoint1: the hinge's axis runs through both");
        }
        if (motor.min_degrees > motor.max_degrees) {
          throw InputError(prefix + "MinAngle", 0,
                           "expected at most " + prefix + "MaxAngle (" + text::FormatDouble(motor.max_degrees) +
                               "°), found " + text::FormatDouble(motor.min_degrees) + "°");
        }
      });
  return applied;
}

}  // namespace orcs::aseries
