// The physics engines a world can run on: the choices of /Simulation/Engine, and of the --engine options of
// orcs-sim and orcs-batch. The first is the default.
#pragma once

#include <string>
#include <vector>

namespace orcs::scene {

inline const std::vector<std::string>& EngineNames() {
  static const std::vector<std::string> names = {"ODE", "MuJoCo"};
  return names;
}

}  // namespace orcs::scene
