// Per-motor and per-board parameters (docs/model.md, "Per-motor parameters"): the real servos differ from one
// another (the original's report, §7.1), and so do the accelerometer boards. Every motor of every agent has its
// own copy of each global motor, angle-sensor and physical-servo value, at /Sim/<agent>/<motor>/... (e.g.
// /Sim/Humanoid/Right/Knee/AngularMotor/PID/Proportional, /Sim/Humanoid/Right/Knee/Servo/Resistance); every
// accelerometer board its own copy of each /AccelSensor/... value, at /Sim/<agent>/<board>/AccelSensor/...
// (e.g. /Sim/Humanoid/ABFR/AccelSensor/Range).
//
// A copy follows its global value — a write to /AngularMotor/PID/Proportional changes every motor's gain — until
// the copy itself is written with another value; from then on it keeps its own. The models read the copies only.
// /Servo/Enabled (which model runs) stays one global switch.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "model/core/variable_repository.h"

namespace orcs::aseries {

/// The path prefix of a motor's or a board's copies: "/Sim/<agent>/<part>" (a global path is appended to it).
std::string PerMotorPrefix(const std::string& agent, const std::string& motor);

/// The global paths each motor has a copy of, each once: the Dynamixel, angle-sensor and servo tables' (not
/// /Servo/Enabled).
const std::vector<std::string_view>& PerMotorPaths();
/// The global paths each accelerometer board has a copy of: the /AccelSensor/... values.
const std::vector<std::string_view>& PerBoardPaths();

/// Registers, at `prefix` + each of `global_paths` (registered already), a copy with the global's current value
/// that follows the global until written. Copies registered already are left as they are.
void AddFollowingCopies(VariableRepository& values, const std::string& prefix,
                        const std::vector<std::string_view>& global_paths);

/// AddFollowingCopies for each motor (PerMotorPaths) and each board (PerBoardPaths) of an agent.
void AddPerMotorParameters(VariableRepository& values, const std::string& agent,
                           const std::vector<std::string>& motors, const std::vector<std::string>& boards = {});

}  // namespace orcs::aseries
