// A controller written as a script that travels in the job (docs/extending.md):
//   {"type": "script", "script": "cpg.lua", "genome_length": 6, "params": {...}, "limits": {...}}
// The script sees the genome as the global table `genome` (genome_length numbers, from index 1) and defines
//   reset()      optional: after the parameter set's reset, before the first control step
//   control(t)   every control step, at simulated time t (the start of the coming step): reads the sensors through
//                the `orcs` table and writes motor commands with orcs.set_angle / orcs.set_torque
// `orcs-batch evolve` searches the genome like any other flat genome. One sandboxed state per parameter set.
#pragma once

#include <memory>
#include <vector>

#include "model/control/controller.h"
#include "model/script/script_spec.h"
#include "model/script/simulation_api.h"

namespace orcs::control {

class ScriptController : public Controller {
 public:
  /// Runs the script's top level for agent `agent_index` of `simulation`, with `genome` as its global `genome`.
  /// Throws InputError for a syntax error or a script without control(t), ScriptFailure for an error or a limit.
  ScriptController(const script::ScriptSpec& spec, const std::vector<double>& genome, scene::Simulation& simulation,
                   int agent_index);

  void Reset() override;
  void Update(double time_seconds) override;

 private:
  const scene::Simulation& simulation_;
  script::SimulationApi api_;
  std::unique_ptr<script::ScriptSandbox> sandbox_;
  int reset_ = -1, control_ = -1;  ///< function references, −1 = not defined
};

}  // namespace orcs::control
