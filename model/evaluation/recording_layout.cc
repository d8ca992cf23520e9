#include "model/evaluation/recording_layout.h"

#include <functional>
#include <unordered_map>

#include "base/demand.h"
#include "model/core/rotation.h"

namespace orcs::evaluation {
namespace {

nlohmann::json Array(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json Array(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

// Components a numeric value contributes as channels, with their suffixes; none for strings and colours.
std::vector<std::string> ComponentSuffixes(ValueType type) {
  switch (type) {
    case ValueType::kBool:
    case ValueType::kInt:
    case ValueType::kDouble: return {""};
    case ValueType::kVector3: return {".x", ".y", ".z"};
    case ValueType::kQuaternion: return {".w", ".x", ".y", ".z"};
    case ValueType::kString:
    case ValueType::kColor: return {};
  }
  return {};
}

float ComponentOf(const Value& value, int component) {
  switch (value.type()) {
    case ValueType::kBool: return value.as_bool() ? 1.0f : 0.0f;
    case ValueType::kInt: return static_cast<float>(value.as_int());
    case ValueType::kDouble: return static_cast<float>(value.as_double());
    case ValueType::kVector3: return static_cast<float>(value.as_vector3()[component]);
    case ValueType::kQuaternion: {
      const Eigen::Quaterniond q = value.as_quaternion();
      const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
      return static_cast<float>(wxyz[component]);
    }
    case ValueType::kString:
    case ValueType::kColor: break;
  }
  ORCS_UNREACHABLE("only numeric values are channels");
  return 0.0f;
}

}  // namespace

std::string_view ShapeName(physics::Shape shape) {
  switch (shape) {
    case physics::Shape::kBox: return "box";
    case physics::Shape::kSphere: return "sphere";
    case physics::Shape::kCapsule: return "capsule";
    case physics::Shape::kPlane: return "plane";
  }
  return "?";
}

nlohmann::json GeomSizeJson(const physics::GeomDescription& geom) {
  switch (geom.shape) {
    case physics::Shape::kBox: return Array(geom.size);
    case physics::Shape::kSphere: return {geom.size.x()};
    case physics::Shape::kCapsule: return {geom.size.x(), geom.size.y()};
    case physics::Shape::kPlane: return nlohmann::json::array();
  }
  return nullptr;
}

RecordingLayout::RecordingLayout(const scene::Simulation& simulation, const RecordingSource& source)
    : simulation_(simulation) {
  header_ = {{"format", "orcs-recording"},
             {"version", 1},
             {"engine", simulation.engine()},
             {"program", source.program},
             {"source",
              {{"environment", source.environment},
               {"scenario", source.scenario},
               {"seed", source.seed},
               {"set", source.set},
               {"genome", source.genome}}}};
  AddChannels();
  DescribeWorld();
  const VariableRepository& values = simulation_.repository();
  header_["step_seconds"] = values.Get("/Simulation/TimeStepSize").as_double() *
                            static_cast<double>(values.Get("/Simulation/IterationsPerStep").as_int());
}

void RecordingLayout::AddChannels() {
  const VariableRepository& repository = simulation_.repository();
  nlohmann::json names = nlohmann::json::array();
  nlohmann::json constants = nlohmann::json::object();
  for (int id = 0; id < repository.size(); ++id) {
    const Value& value = repository.value(id);
    const std::vector<std::string> suffixes = ComponentSuffixes(value.type());
    if (suffixes.empty()) constants[repository.path(id)] = value.ToString();
    for (size_t c = 0; c < suffixes.size(); ++c) {
      channels_.push_back({&value, static_cast<int>(c)});
      names.push_back(repository.path(id) + suffixes[c]);
    }
  }
  header_["channels"] = std::move(names);
  header_["constants"] = std::move(constants);
}

namespace {

// The channel index of a repository value's first component; -1 when the value is not recorded.
using ChannelOf = std::function<int(const std::string& path)>;

nlohmann::json GeomsJson(const physics::BodyDescription& body) {
  nlohmann::json geoms = nlohmann::json::array();
  for (const physics::GeomDescription& geom : body.geoms) {
    nlohmann::json entry = {{"name", geom.name},
                            {"shape", ShapeName(geom.shape)},
                            {"size", GeomSizeJson(geom)},
                            {"offset", Array(geom.offset)},
                            {"rotation", Array(geom.rotation)},
                            {"color", geom.rgba},
                            {"material", geom.material},
                            {"collides", geom.collides}};
    if (!geom.texture.empty()) entry["texture"] = geom.texture;  // optional: absent means none
    geoms.push_back(std::move(entry));
  }
  return geoms;
}

nlohmann::json BodiesJson(const physics::PhysicsModel& physics, const ChannelOf& channel) {
  nlohmann::json bodies = nlohmann::json::array();
  for (int b = 0; b < physics.body_count(); ++b) {
    const physics::BodyDescription& body = physics.body(b);
    nlohmann::json entry = {{"name", body.name},
                            {"dynamic", body.dynamic},
                            {"position", Array(body.position)},
                            {"quaternion", Array(body.orientation)},
                            {"geoms", GeomsJson(body)}};
    const int position = channel("/Sim/" + body.name + "/Position");
    const int quaternion = channel("/Sim/" + body.name + "/OrientationQuaternion");
    if (body.dynamic && position >= 0 && quaternion >= 0) {
      entry["pose_channels"] = {position,       position + 1,   position + 2,  quaternion,
                                quaternion + 1, quaternion + 2, quaternion + 3};
    }
    bodies.push_back(std::move(entry));
  }
  return bodies;
}

// The agents with their motors; `motor_of[j]` gets the motor fields of joint j when a motor drives it.
nlohmann::json AgentsJson(const scene::WorldModel& model, const ChannelOf& channel,
                          std::vector<nlohmann::json>& motor_of) {
  nlohmann::json agents = nlohmann::json::array();
  for (int a = 0; a < static_cast<int>(model.agents().size()); ++a) {
    const aseries::ASeriesLayout& layout = model.agents()[a];
    nlohmann::json motors = nlohmann::json::array();
    for (size_t m = 0; m < layout.motors.size(); ++m) {
      const std::string& motor = model.morphology(a).motors[m].name;
      motors.push_back(motor);
      motor_of[layout.motors[m]] = {{"motor", motor},
                                    {"agent", layout.agent_name},
                                    {"angle_channel", channel("/Sim/" + layout.agent_name + "/" + motor + "/JointAngle")}};
    }
    agents.push_back({{"name", layout.agent_name}, {"type", model.environment().agents[a].type}, {"motors", motors}});
  }
  return agents;
}

nlohmann::json JointsJson(const physics::PhysicsModel& physics, const std::vector<nlohmann::json>& motor_of) {
  nlohmann::json joints = nlohmann::json::array();
  for (int j = 0; j < physics.joint_count(); ++j) {
    const physics::JointDescription& joint = physics.joint(j);
    nlohmann::json entry = {{"name", joint.name},
                            {"type", joint.type == physics::JointType::kHinge ? "hinge" : "fixed"},
                            {"body1", joint.body1},
                            {"body2", joint.body2},
                            {"anchor", Array(joint.anchor)},
                            {"axis", Array(joint.axis.normalized())}};
    if (joint.limited) entry["range"] = {RadiansToDegrees(joint.lo), RadiansToDegrees(joint.hi)};
    if (!motor_of[j].is_null()) entry.update(motor_of[j]);
    joints.push_back(std::move(entry));
  }
  return joints;
}

}  // namespace

// Bodies with geoms and colours, joints with anchors and axes, agents with motors: what the viewer draws.
void RecordingLayout::DescribeWorld() {
  const scene::WorldModel& model = simulation_.model();
  const physics::PhysicsModel& physics = *model.physics();
  const VariableRepository& repository = simulation_.repository();
  std::unordered_map<const Value*, int> channel_of;
  for (size_t c = 0; c < channels_.size(); ++c) channel_of.try_emplace(channels_[c].value, static_cast<int>(c));
  const ChannelOf channel = [&](const std::string& path) {
    const Value* value = repository.Find(path);
    const auto it = channel_of.find(value);
    return value != nullptr && it != channel_of.end() ? it->second : -1;
  };
  std::vector<nlohmann::json> motor_of(physics.joint_count());
  header_["bodies"] = BodiesJson(physics, channel);
  header_["agents"] = AgentsJson(model, channel, motor_of);
  header_["joints"] = JointsJson(physics, motor_of);
}

void RecordingLayout::ReadValues(float* out) const {
  for (std::size_t c = 0; c < channels_.size(); ++c) out[c] = ComponentOf(*channels_[c].value, channels_[c].component);
}

void RecordingLayout::ReadContacts(std::vector<ContactSample>& out) const {
  out.clear();
  for (const physics::Contact& contact : simulation_.physics().contacts()) {
    if (contact.excluded) continue;
    ContactSample sample;
    sample.body1 = contact.body1;
    sample.body2 = contact.body2;
    for (int i = 0; i < 3; ++i) {
      sample.position[i] = static_cast<float>(contact.position[i]);
      sample.normal[i] = static_cast<float>(contact.normal[i]);
    }
    sample.depth = static_cast<float>(contact.depth);
    out.push_back(sample);
  }
}

}  // namespace orcs::evaluation
