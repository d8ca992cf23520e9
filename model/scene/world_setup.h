// The original's way of making a world from the command line (-env, -ival, -val), shared by orcs-sim, orcs-osp
// and orcs-view --live: the environment (or one A-Series "Humanoid" on the floor), initial value files before the
// build, value files after it.
#pragma once

#include <string>
#include <vector>

#include "model/core/value_file.h"
#include "model/scene/simulation.h"

namespace orcs::scene {

/// Loads, builds and configures `simulation`. Throws InputError naming the file and line. Paths of the value
/// files that the world lacks (an old file of the original naming its GUI's values) are refused with kRefuse
/// (--strict), else left out and returned for one warning (IgnoredValues::Warning).
IgnoredValues SetUpWorld(Simulation& simulation, const std::string& environment_file,
                         const std::vector<std::string>& initial_value_files,
                         const std::vector<std::string>& value_files, UnknownPaths unknown = UnknownPaths::kIgnore);

}  // namespace orcs::scene
