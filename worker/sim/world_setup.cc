#include "worker/sim/world_setup.h"

#include "model/core/value_file.h"
#include "model/scene/environment_reader.h"

namespace orcs::sim {

void SetUpWorld(scene::Simulation& simulation, const std::string& environment_file,
                const std::vector<std::string>& initial_value_files, const std::vector<std::string>& value_files) {
  scene::EnvironmentDescription environment;
  if (environment_file.empty()) {
    environment.source = "(default: one A-Series named Humanoid on the floor)";
    environment.agents.push_back(scene::AgentDescription{});
  } else {
    environment = scene::EnvironmentReader::ReadFile(environment_file);
  }
  simulation.LoadEnvironment(environment);
  for (const std::string& file : initial_value_files) ValueFile::Apply(file, simulation.repository());
  simulation.Build();
  for (const std::string& file : value_files) ValueFile::Apply(file, simulation.repository());
}

}  // namespace orcs::sim
