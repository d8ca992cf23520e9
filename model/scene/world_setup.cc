#include "model/scene/world_setup.h"

#include "model/core/value_file.h"
#include "model/scene/environment_reader.h"

namespace orcs::scene {

IgnoredValues SetUpWorld(Simulation& simulation, const std::string& environment_file,
                         const std::vector<std::string>& initial_value_files,
                         const std::vector<std::string>& value_files, UnknownPaths unknown) {
  EnvironmentDescription environment;
  if (environment_file.empty()) {
    environment.source = "(default: one A-Series named Humanoid on the floor)";
    environment.agents.push_back(AgentDescription{});
  } else {
    environment = EnvironmentReader::ReadFile(environment_file);
  }
  simulation.LoadEnvironment(environment);
  IgnoredValues ignored;
  for (const std::string& file : initial_value_files) ignored.Add(ValueFile::Apply(file, simulation.repository(), unknown));
  simulation.Build();
  for (const std::string& file : value_files) ignored.Add(ValueFile::Apply(file, simulation.repository(), unknown));
  return ignored;
}

}  // namespace orcs::scene
