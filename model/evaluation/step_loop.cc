#include "model/evaluation/step_loop.h"

namespace orcs::evaluation {

std::int64_t RunSteps(scene::Simulation& simulation, std::int64_t steps, const StepHooks& hooks) {
  for (std::int64_t i = 0; i < steps; ++i) {
    if (hooks.drive) hooks.drive(i, simulation.time());
    if (simulation.Step() != scene::SimulationStatus::kOk) return i + 1;
    if (hooks.observe && !hooks.observe(i)) return i + 1;
  }
  return steps;
}

}  // namespace orcs::evaluation
