// Errors of orcs: bad user input (InputError, base/input_error.h, here for the model's files) and failed runs.
//
// Every input is checked where it enters (docs/architecture.md, "Errors and bad input"). An InputError names the
// source (a file, or a field of a message), the line where there is one, what was expected and what was
// found, in one line: "scenarios/x.xml:12: object 'Box': attribute 'mass' expected a number, found 'abc'".
// Internal invariants are checked with ORCS_DEMAND (base/demand.h), in every build; they are programming errors, not
// user errors (docs/architecture.md, "Errors and bad input").
#pragma once

#include <stdexcept>
#include <string>

#include "base/input_error.h"  // InputError: every layer's, the broker's too

namespace orcs {

/// The physics engine reported an error (ODE's error or debug handler fired). The world that raised it is
/// no longer usable; the run ends with an error status instead of the process aborting.
class PhysicsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace orcs
