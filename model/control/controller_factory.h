// Making a scenario's controller for one genome (docs/scenarios.md, "controller"):
//   {"type": "network", ...}      a NeuralNetwork; genome = a flat array filling the network's free slots, or
//                                 a full network object (then the scenario's topology is not used)
//   {"type": "oscillator", "joints": ["Right/HipYaw", ...], "torque": 1.0}
//                                 a SineOscillator; genome = 4 numbers per joint
//   {"type": "keyframes", "record": {"file", "text"}}
//                                 a KeyframePlayer; genome = [] (nothing to evolve)
//   {"type": "script", "script": {"file", "text"}, "genome_length": N, "params": {...}}
//                                 a ScriptController (docs/extending.md); genome = N numbers
//   {"type": "plugin", "plugin": "example/hold_pose", "genome_length": N, "params": {...}}
//                                 a PluginController (a worker's compiled plug-in); genome = N numbers
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/control/controller.h"
#include "model/core/variable_repository.h"
#include "model/scene/simulation.h"
#include "model/script/plugin_registry.h"

namespace orcs::control {

/// What the controller acts on.
struct ControlTarget {
  std::string agent;                 ///< agent name
  std::vector<std::string> motors;   ///< the agent's motor names, motor order
};

/// Checks a controller section without a world; returns the genome length it expects for a flat genome.
/// Throws InputError "source: field 'controller.x' ..." for unknown types, keys or malformed parts.
int CheckController(const nlohmann::json& controller, const ControlTarget& target, const std::string& source);

/// Checks a genome against a controller section (length, type); throws InputError "source: genome ...".
void CheckGenome(const nlohmann::json& controller, const nlohmann::json& genome, const ControlTarget& target,
                 const std::string& source);

/// The controller for `genome`, bound to `values`. Throws InputError as the two checks do, or naming an
/// unknown repository value.
std::unique_ptr<Controller> MakeController(const nlohmann::json& controller, const nlohmann::json& genome,
                                           const ControlTarget& target, VariableRepository& values,
                                           const std::string& source);

/// The same for agent `agent_index` of `simulation`, which every controller type can be made for (a script or
/// plug-in controller reads the simulation). Throws InputError as above, ScriptFailure when a script's top level
/// fails, PluginMissing when `plugins` (null: none) lacks the plug-in named.
std::unique_ptr<Controller> MakeController(const nlohmann::json& controller, const nlohmann::json& genome,
                                           const ControlTarget& target, scene::Simulation& simulation,
                                           int agent_index, const std::string& source,
                                           const script::PluginRegistry* plugins = nullptr);

}  // namespace orcs::control
