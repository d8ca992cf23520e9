#include "model/aseries/per_motor_parameters.h"

#include <memory>
#include <set>

#include "model/aseries/accelerometer.h"
#include "model/aseries/angle_sensor.h"
#include "model/aseries/dynamixel_motor.h"
#include "model/aseries/servo_motor.h"

namespace orcs::aseries {
namespace {

// Whether a copy still follows its global value, and whether the global is writing it right now (a write of
// the global's value is no write of the copy's own).
struct Following {
  bool following = true;
  bool copying = false;
};

// The paths of `tables`, in table order, each once (IncludeNoise is in two), leaving out `except`.
template <typename... Tables>
std::vector<std::string_view> PathsOf(std::string_view except, const Tables&... tables) {
  std::vector<std::string_view> paths;
  std::set<std::string_view> seen{except};
  const auto add = [&](const auto& table) {
    for (const auto& field : table) {
      if (seen.insert(field.path).second) paths.push_back(field.path);
    }
  };
  (add(tables), ...);
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

const std::vector<std::string_view>& PerMotorPaths() {
  static const std::vector<std::string_view> paths =
      PathsOf(kServoEnabledPath, kDynamixelParameterTable, kAngleSensorParameterTable, kServoParameterTable);
  return paths;
}

const std::vector<std::string_view>& PerBoardPaths() {
  static const std::vector<std::string_view> paths = PathsOf("", kAccelerometerParameterTable);
  return paths;
}

void AddFollowingCopies(VariableRepository& values, const std::string& prefix,
                        const std::vector<std::string_view>& global_paths) {
  for (const std::string_view global_path : global_paths) {
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

void AddPerMotorParameters(VariableRepository& values, const std::string& agent,
                           const std::vector<std::string>& motors, const std::vector<std::string>& boards) {
  for (const std::string& motor : motors) AddFollowingCopies(values, PerMotorPrefix(agent, motor), PerMotorPaths());
  for (const std::string& board : boards) AddFollowingCopies(values, PerMotorPrefix(agent, board), PerBoardPaths());
}

}  // namespace orcs::aseries
