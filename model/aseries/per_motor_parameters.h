// Per-motor motor and angle-sensor parameters (docs/model.md, "Per-motor parameters"): the real servos differ from
// one another (the original's report, §7.1), so every motor of every agent has its own copy of each global
// /AngularMotor/... value, at /Sim/<agent>/<motor>/AngularMotor/... (e.g.
// /Sim/Humanoid/Right/Knee/AngularMotor/PID/Proportional).
//
// A copy follows its global value — a write to /AngularMotor/PID/Proportional changes every motor's gain — until
// the copy itself is written with another value; from then on that motor keeps its own. The motor model reads the
// copies only.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "model/core/variable_repository.h"

namespace orcs::aseries {

/// The path prefix of motor `motor`'s copies: "/Sim/<agent>/<motor>" (a global path is appended to it).
std::string PerMotorPrefix(const std::string& agent, const std::string& motor);

/// Registers, for each motor, a copy of every global motor and angle-sensor parameter (which must be registered
/// already, ASeriesAgent::AddSharedParameters) with the global's current value, and makes it follow the global.
/// Copies registered already are left as they are.
void AddPerMotorParameters(VariableRepository& values, const std::string& agent,
                           const std::vector<std::string>& motors);

}  // namespace orcs::aseries
