// The Dynamixel's angle sensor (spec/aseries.md §6d): the joint angle in degrees, with Gaussian noise, clamped
// to the sensor range. Pure computation; the caller reads the joint angle after the physics step and stores
// the result as <motor>/JointAngle. Decisions: docs/model.md, "Sensors".
#pragma once

#include <array>

#include "model/aseries/parameter_table.h"

namespace orcs {
class RandomStream;
}

namespace orcs::aseries {

struct AngleSensorParameters {
  double noise_deviation = 0.189076;  ///< σ of the reading noise, degrees, /AngularMotor/SensorNoiseDeviation
  bool include_noise = true;          ///< noise switch (shared with the motor), /AngularMotor/IncludeNoise
  double min_angle = -150.0;  ///< lowest reading, degrees; per motor, /Sim/<agent>/<motor>/MinSensorAngle
  double max_angle = 150.0;   ///< highest reading, degrees; per motor, /Sim/<agent>/<motor>/MaxSensorAngle
};

/// Repository paths of the global AngleSensorParameters fields (the per-motor sensor range is not global and
/// not in the table).
inline constexpr std::array<ParameterField<AngleSensorParameters>, 2> kAngleSensorParameterTable{{
    {"/AngularMotor/SensorNoiseDeviation", &AngleSensorParameters::noise_deviation},
    {"/AngularMotor/IncludeNoise", &AngleSensorParameters::include_noise},
}};

/// The reading of joint angle `angle_rad`: degrees + Normal(0, noise_deviation) when include_noise,
/// noise_deviation > 0 and `noise` is given, clamped to [min_angle, max_angle].
double MeasureJointAngle(double angle_rad, const AngleSensorParameters& parameters, RandomStream* noise);

}  // namespace orcs::aseries
