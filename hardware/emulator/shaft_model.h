// What turns an emulated servo's shaft: the servo-bus emulator asks it where each shaft is after the goals it was
// given. The emulator's own is kinematic (each shaft moves towards its goal at the no-load speed, by the wall
// clock); hardware/robot/simulated_shafts.h puts orcs's simulation behind the bus — the servo model on a pendulum
// or the A-Series, hidden effects and all — advanced one control period per goal write, so that a recording
// through the bus is the same at any machine load.
#pragma once

#include <cstddef>

namespace orcs::hardware {

class ShaftModel {
 public:
  virtual ~ShaftModel() = default;
  /// Servo `index` (the emulator's ids in their order) now holds `goal_deg` (degrees) with `torque` (0…1 of its
  /// maximum: its torque limit register; 0 when its torque is off).
  virtual void Command(std::size_t index, double goal_deg, double torque) = 0;
  /// One control period has passed under the goals given: move the shafts on by `seconds`.
  virtual void Advance(double seconds) = 0;
  /// Servo `index`'s shaft angle (degrees) and speed (°/s) now.
  virtual double Angle(std::size_t index) const = 0;
  virtual double Speed(std::size_t index) const = 0;
};

}  // namespace orcs::hardware
