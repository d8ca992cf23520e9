#include "model/control/sine_oscillator.h"

#include <cmath>
#include <numbers>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::control {

SineOscillator::SineOscillator(std::vector<SineJoint> joints, const std::string& agent, std::optional<double> torque,
                               VariableRepository& values, const std::string& source)
    : joints_(std::move(joints)), torque_(torque) {
  for (const SineJoint& joint : joints_) {
    const std::string prefix = "/Sim/" + agent + "/" + joint.motor + "/";
    Value* angle = values.Find(prefix + "DesiredAngle");
    if (angle == nullptr) {
      throw InputError(source, 0, "controller: agent " + text::Quote(agent) + " has no motor " + text::Quote(joint.motor));
    }
    angles_.push_back(angle);
    if (torque_) torques_.push_back(&values.Get(prefix + "DesiredTorque"));
  }
}

void SineOscillator::Reset() {
  for (Value* torque : torques_) torque->Set(*torque_);
}

void SineOscillator::Update(double time_seconds) {
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const SineJoint& joint = joints_[j];
    const double angle =
        joint.offset + joint.amplitude * std::sin(2 * std::numbers::pi * joint.frequency * time_seconds + joint.phase);
    angles_[j]->Set(angle);
  }
}

}  // namespace orcs::control
