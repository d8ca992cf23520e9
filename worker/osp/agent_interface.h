// An agent as OSP sees it (spec/aseries.md §4d): its inputs (per motor DesiredAngle then DesiredTorque) and
// outputs (per motor JointAngle, then per board AccelAxis1 and AccelAxis2), each a repository value with its
// interface name (no agent prefix, e.g. "/Right/Knee/DesiredAngle") and its raw ↔ normalised range. No info
// values (the A-Series has none).
#pragma once

#include <string>
#include <vector>

#include "model/aseries/value_range.h"
#include "model/core/value.h"
#include "model/scene/simulation.h"

namespace orcs::osp {

/// One input or output of an agent.
struct InterfaceValue {
  std::string name;           ///< interface name, e.g. "/Right/Knee/DesiredAngle"
  Value* value = nullptr;     ///< the repository value (a double)
  aseries::ValueRange range;  ///< raw ↔ normalised mapping
};

struct AgentInterface {
  std::string name;                    ///< the agent's name, e.g. "Humanoid"
  std::vector<InterfaceValue> inputs;  ///< 2 per motor, motor order
  std::vector<InterfaceValue> outputs; ///< 1 per motor, then 2 per board, board order
};

/// The interface of agent `index` of a built simulation (its values stay valid while the simulation lives).
AgentInterface MakeAgentInterface(scene::Simulation& simulation, int index);

}  // namespace orcs::osp
