// What writes an agent's inputs: a neural network, a sine oscillator per joint, a keyframe record. Before every
// simulation step the evaluation calls Update with the step's start time; a controller reads the agent's
// output values from the repository and writes its input values there (the same values an OSP client sees).
#pragma once

namespace orcs::control {

class Controller {
 public:
  virtual ~Controller() = default;
  /// Back to the initial state, after the simulation's Reset.
  virtual void Reset() = 0;
  /// One control step at simulated time `time_seconds` (the start of the coming simulation step).
  virtual void Update(double time_seconds) = 0;
};

}  // namespace orcs::control
