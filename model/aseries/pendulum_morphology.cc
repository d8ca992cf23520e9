#include "model/aseries/pendulum_morphology.h"

#include <cmath>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::aseries {
namespace {

void CheckPositive(double value, const char* field) {
  if (!(value > 0) || !std::isfinite(value)) {
    throw InputError("pendulum rig", 0,
                     std::string("field '") + field + "' expected a positive number, found " + text::FormatDouble(value));
  }
}

}  // namespace

ASeriesMorphology MakePendulumMorphology(const PendulumPole& pole) {
  CheckPositive(pole.mass, "poleMass");
  CheckPositive(pole.length, "poleLength");
  CheckPositive(pole.width, "poleWidth");
  ASeriesMorphology morphology;
  MorphologyBody body;
  body.name = kPendulumPole;
  body.size = {pole.width, pole.length, pole.width};
  body.centre = {0.0, -pole.length / 2, 0.0};
  body.mass = pole.mass;
  body.material = "Default";
  body.color = {192, 192, 200, 255};
  morphology.bodies.push_back(body);
  morphology.root_body = kPendulumPole;  // moot: the motor clamps the pole to the world, which is the root then
  MorphologyMotor motor;
  motor.name = kPendulumMotor;
  motor.first_body = kPendulumPole;
  motor.second_body = "";  // the static world: the motor housing is clamped to the rig's frame
  motor.axis_point1 = Eigen::Vector3d::Zero();
  motor.axis_point2 = Eigen::Vector3d::UnitZ();
  motor.min_degrees = -150.0;
  motor.max_degrees = 150.0;
  morphology.motors.push_back(motor);
  return morphology;
}

}  // namespace orcs::aseries
