// The driven pendulum rig the original team used to study the torque-controlled motor: one AX-12+ whose
// housing is fixed to the world turns an aluminium pole about a horizontal axis. It is an agent like the
// A-Series (same Dynamixel model and parameters, one motor called "Motor", no accelerometers), so records,
// value files, logs and the gap workflow treat both alike.
//
// Frame: the hinge is at the placement origin with its axis along +Z; at joint angle 0 the pole hangs straight
// down (−Y). Units: metres, kilograms.
#pragma once

#include "model/aseries/aseries_morphology.h"

namespace orcs::aseries {

/// The rig's pole.
struct PendulumPole {
  double mass = 0.5;     ///< kg (the original's 500 g aluminium pole)
  double length = 0.3;   ///< m, from the axis to the tip
  double width = 0.025;  ///< m, square cross-section edge
};

/// Name of the rig's only motor and of its pole body.
inline constexpr char kPendulumMotor[] = "Motor";
inline constexpr char kPendulumPole[] = "Pole";

/// The rig as a morphology: body "Pole" hinged to the static world by motor "Motor" (range ±150°).
/// Throws InputError naming the field when a pole dimension or the mass is not a positive finite number.
ASeriesMorphology MakePendulumMorphology(const PendulumPole& pole);

}  // namespace orcs::aseries
