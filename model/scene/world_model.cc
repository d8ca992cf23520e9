#include "model/scene/world_model.h"

#include "model/aseries/aseries_morphology.h"
#include "model/aseries/morphology_values.h"
#include "model/aseries/pendulum_morphology.h"
#include "model/core/error.h"
#include "model/core/rotation.h"
#include "model/core/text.h"

namespace orcs::scene {
namespace {

constexpr double kMaxObjectMass = 1e6;  // kg
constexpr double kMinObjectSize = 1e-6;  // m
constexpr double kMaxObjectSize = 1e6;   // m

std::string ObjectPath(const std::string& object, const char* value) { return "/Sim/" + object + "/" + value; }

// Reads a value the object registered and checks it still makes sense after value files changed it.
double PositiveValue(const VariableRepository& values, const std::string& object, const char* name,
                     bool allow_zero) {
  const std::string path = ObjectPath(object, name);
  const double value = values.Get(path).as_double();
  if (!(value > 0 || (allow_zero && value == 0)) || std::isinf(value)) {
    throw InputError(path, 0, "expected a positive number, found " + text::FormatDouble(value));
  }
  return value;
}

physics::BodyDescription MakeBody(const ObjectDescription& object, const VariableRepository& values) {
  const std::string& name = object.name;
  physics::BodyDescription body;
  body.name = name;
  body.dynamic = values.Get(ObjectPath(name, "Dynamic")).as_bool();
  body.mass = PositiveValue(values, name, "Mass", !body.dynamic);
  body.position = values.Get(ObjectPath(name, "Position")).as_vector3();
  body.orientation = QuaternionFromEulerDegrees(values.Get(ObjectPath(name, "Orientation")).as_vector3());
  body.static_friction = values.Get(ObjectPath(name, "StaticFriction")).as_double();
  body.dynamic_friction = values.Get(ObjectPath(name, "DynamicFriction")).as_double();
  body.elasticity = values.Get(ObjectPath(name, "Elasticity")).as_double();
  physics::GeomDescription geom;
  geom.material = values.Get(ObjectPath(name, "Material")).as_string();
  const Color color = values.Get(ObjectPath(name, "Color")).as_color();
  geom.rgba = {color.r, color.g, color.b, color.a};
  geom.texture = values.Get(ObjectPath(name, "Texture")).as_string();
  if (object.type == ObjectType::kBox) {
    geom.shape = physics::Shape::kBox;
    geom.size = {PositiveValue(values, name, "Width", false), PositiveValue(values, name, "Height", false),
                 PositiveValue(values, name, "Depth", false)};
  } else {
    geom.shape = physics::Shape::kSphere;
    geom.size = {PositiveValue(values, name, "Radius", false), 0.0, 0.0};
  }
  body.geoms.push_back(geom);
  return body;
}

physics::BodyDescription MakeFloor(const VariableRepository& values) {
  physics::BodyDescription floor;
  floor.name = "Floor";
  floor.dynamic = false;
  physics::GeomDescription plane;
  plane.shape = physics::Shape::kPlane;
  plane.material = values.Get("/Sim/Floor/Material").as_string();
  floor.geoms.push_back(plane);
  return floor;
}

// A fixed joint welding the held body to the world where it starts: the robot hangs in a test stand.
physics::JointDescription StandJoint(const AgentDescription& agent) {
  physics::JointDescription joint;
  joint.name = agent.name + "/Stand";
  joint.type = physics::JointType::kFixed;
  joint.body1 = agent.name + "/" + agent.hold_body;
  joint.body2 = "";  // the static world
  return joint;
}

}  // namespace

std::shared_ptr<const aseries::ASeriesMorphology> WorldModel::MorphologyOf(const AgentDescription& agent) {
  if (agent.type == "Pendulum") {
    return std::make_shared<const aseries::ASeriesMorphology>(
        aseries::MakePendulumMorphology({.mass = agent.pole_mass, .length = agent.pole_length}));
  }
  if (agent.morphology) return agent.morphology;  // from a robot file
  // The embedded A-Series morphology lives for the whole process; share it without owning it.
  return {std::shared_ptr<const aseries::ASeriesMorphology>(), &aseries::DefaultASeriesMorphology()};
}

void WorldModel::RegisterObjectValues(const EnvironmentDescription& environment, VariableRepository& values) {
  values.Add("/Sim/Floor/Material", environment.floor_material);
  for (const ObjectDescription& object : environment.objects) {
    const auto path = [&object](const char* value) { return ObjectPath(object.name, value); };
    values.Add(path("Position"), object.position);
    values.Add(path("Orientation"), object.orientation);
    values.Add(path("OrientationQuaternion"), QuaternionFromEulerDegrees(object.orientation));
    values.Add(path("Dynamic"), object.dynamic);
    // Ranges refuse where it is written what the world could not be compiled with (the compile checks again).
    values.Add(path("Mass"), object.mass).SetRange(0.0, kMaxObjectMass);
    values.Add(path("Material"), object.material);
    values.Add(path("Color"), object.color);
    values.Add(path("Texture"), object.texture);
    if (object.type == ObjectType::kBox) {
      values.Add(path("Width"), object.dimension.x()).SetRange(kMinObjectSize, kMaxObjectSize);
      values.Add(path("Height"), object.dimension.y()).SetRange(kMinObjectSize, kMaxObjectSize);
      values.Add(path("Depth"), object.dimension.z()).SetRange(kMinObjectSize, kMaxObjectSize);
    } else {
      values.Add(path("Radius"), object.dimension.x()).SetRange(kMinObjectSize, kMaxObjectSize);
    }
    // Fallback friction for unknown materials: the original's body defaults.
    values.Add(path("StaticFriction"), 0.0);
    values.Add(path("DynamicFriction"), 0.0);
    values.Add(path("Elasticity"), 0.05);
  }
  // Agent bodies publish their pose; their structure values are the morphology's (model/aseries).
  for (const AgentDescription& agent : environment.agents) {
    const Eigen::Quaterniond orientation = QuaternionFromEulerDegrees(agent.orientation);
    const std::shared_ptr<const aseries::ASeriesMorphology> morphology = MorphologyOf(agent);
    for (const aseries::MorphologyBody& body : morphology->bodies) {
      const std::string prefix = "/Sim/" + agent.name + "/" + body.name + "/";
      values.Add(prefix + "Position", Eigen::Vector3d(agent.position + orientation * body.centre));
      values.Add(prefix + "Orientation", agent.orientation);
      values.Add(prefix + "OrientationQuaternion", orientation);
    }
    aseries::AddMorphologyValues(*morphology, agent.name, values);
  }
}

std::vector<WorldModel::StructureValue> WorldModel::StructurePaths(const EnvironmentDescription& environment) {
  std::vector<StructureValue> paths = {{"/Sim/Floor/Material", "", false}};
  for (const ObjectDescription& object : environment.objects) {
    const auto add = [&](const char* value, bool pose = false) { paths.push_back({ObjectPath(object.name, value), "", pose}); };
    add("Position", true);
    add("Orientation", true);
    for (const char* value : {"Dynamic", "Mass", "Material", "Color", "Texture"}) add(value);
    if (object.type == ObjectType::kBox) {
      for (const char* value : {"Width", "Height", "Depth"}) add(value);
    } else {
      add("Radius");
    }
    for (const char* value : {"StaticFriction", "DynamicFriction", "Elasticity"}) add(value);
  }
  for (const AgentDescription& agent : environment.agents) {
    for (std::string& path : aseries::MorphologyValuePaths(*MorphologyOf(agent), agent.name)) {
      paths.push_back({std::move(path), "", false});
    }
  }
  return paths;
}

std::shared_ptr<const WorldModel> WorldModel::Compile(const EnvironmentDescription& environment,
                                                      const VariableRepository& values) {
  physics::PhysicsDescription description;
  description.bodies.push_back(MakeFloor(values));
  for (const ObjectDescription& object : environment.objects) description.bodies.push_back(MakeBody(object, values));
  std::shared_ptr<WorldModel> model(new WorldModel());
  for (const AgentDescription& agent : environment.agents) {
    const aseries::ASeriesPlacement placement{agent.name, agent.position, QuaternionFromEulerDegrees(agent.orientation)};
    auto morphology = std::make_shared<const aseries::ASeriesMorphology>(
        aseries::ApplyMorphologyValues(*MorphologyOf(agent), agent.name, values));
    model->agents_.push_back(aseries::AddASeries(*morphology, placement, description));
    if (!agent.hold_body.empty()) description.joints.push_back(StandJoint(agent));
    model->morphologies_.push_back(std::move(morphology));
  }
  model->environment_ = environment;
  model->structure_ = StructurePaths(environment);
  for (StructureValue& value : model->structure_) value.text = values.Get(value.path).ToString();
  model->physics_ = std::make_shared<const physics::PhysicsModel>(std::move(description));
  return model;
}

}  // namespace orcs::scene
