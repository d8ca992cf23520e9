// The loop every run of a controller shares (a job's parameter set, orcs-sim's run): before each step the
// controllers write the motor inputs, then the simulation steps, then the observers sample — fitness terms, logs,
// recordings, clocks. One place, so that what "a run" means cannot drift between programs. orcs-osp and orcs-view's
// live mode step one step at a time on request and call Simulation::Step themselves.
#pragma once

#include <cstdint>
#include <functional>

#include "model/scene/simulation.h"

namespace orcs::evaluation {

/// What happens around each step of a run.
struct StepHooks {
  /// Before step `step` (counted from 0 in this RunSteps call): controllers write the motor inputs for simulated time
  /// `time`, s. May be empty.
  std::function<void(std::int64_t step, double time)> drive;
  /// After each step the simulation took without trouble: fitness, logs, recording. Returns false to stop the run
  /// (a time limit). May be empty.
  std::function<bool(std::int64_t step)> observe;
};

/// Runs up to `steps` steps of drive → Step → observe. Stops early when a step leaves the simulation's status
/// not ok (the step is then not observed; see Simulation::status and message) or when observe returns false.
/// Returns the steps taken.
std::int64_t RunSteps(scene::Simulation& simulation, std::int64_t steps, const StepHooks& hooks);

}  // namespace orcs::evaluation
