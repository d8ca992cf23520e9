// The original's way of making a world from the command line (-env, -ival, -val), shared by orcs-sim, orcs-osp
// and orcs-view --live: the environment (or one A-Series "Humanoid" on the floor), initial value files before the
// build, value files after it.
#pragma once

#include <string>
#include <vector>

#include "model/scene/simulation.h"

namespace orcs::scene {

/// Loads, builds and configures `simulation`. Throws InputError naming the file and line.
void SetUpWorld(Simulation& simulation, const std::string& environment_file,
                const std::vector<std::string>& initial_value_files, const std::vector<std::string>& value_files);

}  // namespace orcs::scene
