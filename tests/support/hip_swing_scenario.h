// The scenario the multi-process tests run when the physics itself is not what they test: the A-Series standing,
// its hips swinging (an oscillator on both hip yaw joints), the distance walked as its fitness. About a second of
// work on one core per 10 simulated seconds.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace orcs::test_support {

/// The scenario's JSON text for `duration` simulated seconds, named `name` ("" = no name).
inline std::string HipSwingScenarioText(double duration, const std::string& name = "") {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "genome": [10.0, 1.0, 0.0, 0.0, 10.0, 1.0, 3.0, 0.0],
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]}})");
  scenario["duration"] = duration;
  if (!name.empty()) scenario["name"] = name;
  return scenario.dump();
}

}  // namespace orcs::test_support
