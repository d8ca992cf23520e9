#include "model/aseries/per_motor_parameters.h"

#include <memory>
#include <set>

#include "model/aseries/angle_sensor.h"
#include "model/aseries/dynamixel_motor.h"

namespace orcs::aseries {
namespace {

// Whether a copy still follows its global value, and whether the global is writing it right now (a write of
// the global's value is no write of the motor's own).
struct Following {
  bool following = true;
  bool copying = false;
};

// The global paths that have per-motor copies, in table order, each once (IncludeNoise is in both tables).
std::vector<std::string_view> CopiedPaths() {
  std::vector<std::string_view> paths;
  std::set<std::string_view> seen;
  const auto add = [&](std::string_view path) {
    if (seen.insert(path).second) paths.push_back(path);
  };
  for (const auto& field : kDynamixelParameterTable) add(field.path);
  for (const auto& field : kAngleSensorParameterTable) add(field.path);
  return paths;
}

Value& AddCopy(VariableRepository& values, const std::string& path, const Value& global) {
  switch (global.type()) {
    case ValueType::kBool: return values.Add(path, global.as_bool());
    case ValueType::kInt: return values.Add(path, global.as_int());
    default: return values.Add(path, global.as_double());
  }
}

}  // namespace

std::string PerMotorPrefix(const std::string& agent, const std::string& motor) { return "/Sim/" + agent + "/" + motor; }

void AddPerMotorParameters(VariableRepository& values, const std::string& agent,
                           const std::vector<std::string>& motors) {
  static const std::vector<std::string_view> kCopied = CopiedPaths();
  for (const std::string& motor : motors) {
    const std::string prefix = PerMotorPrefix(agent, motor);
    for (const std::string_view global_path : kCopied) {
      const std::string path = prefix + std::string(global_path);
      if (values.Find(path) != nullptr) continue;
      Value& global = values.Get(global_path);
      Value& copy = AddCopy(values, path, global);
      auto state = std::make_shared<Following>();
      global.AddObserver([&values, path, state](const Value& changed) {
        if (!state->following) return;
        state->copying = true;
        values.Set(path, changed.ToString());
        state->copying = false;
      });
      copy.AddObserver([state](const Value&) {
        if (!state->copying) state->following = false;
      });
    }
  }
}

}  // namespace orcs::aseries
