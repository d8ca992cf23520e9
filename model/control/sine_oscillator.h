// One sine oscillator per joint (docs/scenarios.md, "oscillator"): DesiredAngle(t) = offset + amplitude ·
// sin(2π · frequency · t + phase), clamped to the joint's range by the player of the value (the motor). The
// genome holds four numbers per joint, in the scenario's joint order: amplitude (degrees), frequency (Hz),
// phase (rad), offset (degrees).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model/control/controller.h"
#include "model/core/value.h"
#include "model/core/variable_repository.h"

namespace orcs::control {

struct SineJoint {
  std::string motor;         ///< motor name, e.g. "Right/HipYaw"
  double amplitude = 0.0;    ///< degrees
  double frequency = 0.0;    ///< Hz
  double phase = 0.0;        ///< rad
  double offset = 0.0;       ///< degrees
};

class SineOscillator : public Controller {
 public:
  static constexpr int kGenesPerJoint = 4;

  /// Binds /Sim/<agent>/<motor>/DesiredAngle (and DesiredTorque when `torque` is given: a raw −1…1 value
  /// written once per Reset). Throws InputError naming an unknown motor.
  SineOscillator(std::vector<SineJoint> joints, const std::string& agent, std::optional<double> torque,
                 VariableRepository& values, const std::string& source);

  void Reset() override;
  void Update(double time_seconds) override;

 private:
  std::vector<SineJoint> joints_;
  std::vector<Value*> angles_;   // DesiredAngle per joint
  std::vector<Value*> torques_;  // DesiredTorque per joint (when a torque is given)
  std::optional<double> torque_;
};

}  // namespace orcs::control
