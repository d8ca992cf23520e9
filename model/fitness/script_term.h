// A fitness term written as a script that travels in the job (docs/extending.md):
//   {"type": "script", "name": "head_level", "weight": 1, "script": "head_level.lua", "params": {...},
//    "limits": {"instructions": N, "memory_mib": M}}
// The script defines global functions, each optional but finish:
//   start()      after the parameter set's reset and start pose, before the first step
//   step(dt)     after every simulation step of dt seconds
//   stop()       after step: true ends the parameter set here (the robot fell); the term's value is still finish()'s
//   finish()     at the end: the term's value, a finite number
// and reads the simulation through the `orcs` table (model/script/simulation_api.h). One sandboxed state per parameter
// set: nothing a script keeps carries over to the next set.
#pragma once

#include <memory>
#include <optional>

#include "model/fitness/fitness_terms.h"
#include "model/script/script_spec.h"
#include "model/script/simulation_api.h"

namespace orcs::fitness {

class ScriptTerm : public FitnessTerm {
 public:
  /// Runs the script's top level for agent `agent_index` of `simulation`. Throws InputError for a syntax error or
  /// a script without finish(), ScriptFailure for an error or a limit in its top level.
  ScriptTerm(const script::ScriptSpec& spec, const scene::Simulation& simulation, int agent_index);

  void Start(const scene::Simulation& simulation) override;
  void Sample(const scene::Simulation& simulation, double dt) override;
  /// finish()'s number, called once at the first request after the run. Throws ScriptFailure.
  double value() const override;
  bool finished() const override { return stopped_; }

 private:
  script::SimulationApi api_;
  std::unique_ptr<script::ScriptSandbox> sandbox_;
  int start_ = -1, step_ = -1, stop_ = -1, finish_ = -1;  ///< function references, −1 = not defined
  bool stopped_ = false;
  mutable std::optional<double> value_;  ///< finish()'s, once called
};

}  // namespace orcs::fitness
