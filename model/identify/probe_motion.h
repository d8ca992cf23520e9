// Motions that tell two effects apart (docs/gap.md, "When two effects explain the data"): when the held-out runs
// cannot choose between two fitted models, orcs-gap replays both on each probe motion and names the one where
// their predictions differ most; `orcs-gap synth --probe NAME` makes it, as a keyframe record to play on the robot
// and as a synthetic run. A probe moves one motor through a pattern that shows some effects and not others (slow
// reversals show friction at low speed and its memory, loaded lowering and lifting show load-dependent friction);
// every other motor holds 0° at the default torque.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "model/identify/measured_run.h"
#include "model/identify/replay.h"

namespace orcs::identify {

/// One probe motion of one motor, one row per rig step.
struct ProbeMotion {
  std::string name;                 ///< "slow_reversals": what `orcs-gap synth --probe` takes
  std::string description;          ///< what it does, one line
  std::string shows;                ///< what it shows, one line ("friction at low speed and its memory")
  std::string motor;                ///< the motor it moves
  std::vector<double> angle;        ///< the motor's DesiredAngle per row, degrees
  std::vector<double> torque;       ///< the motor's DesiredTorque per row, −1…1
};

/// The names of every probe, in a fixed order.
const std::vector<std::string_view>& ProbeNames();

/// Every probe for `motor` (one of rig.motors) at the rig's step; each stays within the motor's range
/// [min_degrees, max_degrees]. Throws InputError for a motor the rig lacks.
std::vector<ProbeMotion> ProbeMotions(const Rig& rig, const std::string& motor);

/// The probe called `name`, or throws InputError listing the names.
ProbeMotion FindProbe(const Rig& rig, const std::string& motor, const std::string& name);

/// The probe as a measured run of the rig's agent (every motor commanded and "measured" at 0°, for a replay that
/// logs the simulated angles); the servo's inputs of the run (its firmware gain) are those of `like`, the first fit
/// run, when it has them.
MeasuredRun ProbeRun(const Rig& rig, const ProbeMotion& probe, const MeasuredRun* like);

}  // namespace orcs::identify
