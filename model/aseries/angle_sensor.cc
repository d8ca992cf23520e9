#include "model/aseries/angle_sensor.h"

#include <algorithm>

#include "model/core/random_stream.h"
#include "model/core/rotation.h"

namespace orcs::aseries {

double MeasureJointAngle(double angle_rad, const AngleSensorParameters& parameters, RandomStream* noise) {
  double reading = RadiansToDegrees(angle_rad);
  if (parameters.include_noise && parameters.noise_deviation > 0.0 && noise != nullptr) {
    reading += noise->Normal(0.0, parameters.noise_deviation);
  }
  // min/max rather than std::clamp, which is undefined for a (mis-set) empty range.
  return std::min(std::max(reading, parameters.min_angle), parameters.max_angle);
}

}  // namespace orcs::aseries
