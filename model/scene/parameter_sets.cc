#include "model/scene/parameter_sets.h"

#include <algorithm>
#include <cmath>

#include "model/core/error.h"
#include "model/core/random_stream.h"
#include "model/core/text.h"

namespace orcs::scene {
namespace {

double NominalValue(const VariableRepository& nominal, const ParameterDistribution& distribution, std::size_t i,
                    const std::string& source) {
  const Value* value = nominal.Find(distribution.path);
  const std::string field = "field 'randomisation.parameters[" + std::to_string(i) + "].path' ";
  if (value == nullptr) throw InputError(source, 0, field + "names an unknown repository path " + text::Quote(distribution.path));
  if (value->type() != ValueType::kDouble && value->type() != ValueType::kInt) {
    throw InputError(source, 0, field + "expected the path of a number, found '" + distribution.path +
                                    "' holding " + value->ToString());
  }
  return value->type() == ValueType::kDouble ? value->as_double() : static_cast<double>(value->as_int());
}

double Draw(const ParameterDistribution& distribution, double nominal, RandomStream& stream) {
  const double scale = distribution.relative ? nominal : 1.0;
  if (distribution.kind == ParameterDistribution::Kind::kUniform) {
    return scale * stream.Uniform(distribution.low, distribution.high);
  }
  const double drawn = stream.Normal(distribution.mean, distribution.deviation);
  return scale * std::clamp(drawn, distribution.low, distribution.high);
}

// One initial angle per motor, uniform in ±amplitude, clamped to the motor's range; none when amplitude is 0.
std::vector<double> DrawMotorAngles(double amplitude, const std::vector<aseries::MorphologyMotor>& motors,
                                    RandomStream& stream) {
  std::vector<double> angles;
  if (amplitude == 0.0) return angles;
  for (const aseries::MorphologyMotor& motor : motors) {
    angles.push_back(std::clamp(stream.Uniform(-amplitude, amplitude), motor.min_degrees, motor.max_degrees));
  }
  return angles;
}

}  // namespace

std::vector<ParameterSet> DrawParameterSets(const Randomisation& randomisation, std::uint64_t seed,
                                            const VariableRepository& nominal,
                                            const std::vector<aseries::MorphologyMotor>& motors,
                                            const std::string& source) {
  std::vector<double> nominal_values;
  for (std::size_t i = 0; i < randomisation.parameters.size(); ++i) {
    nominal_values.push_back(NominalValue(nominal, randomisation.parameters[i], i, source));
  }
  std::vector<ParameterSet> sets;
  for (int k = 0; k < randomisation.sets; ++k) {
    RandomStream stream(seed, "parameter-set", static_cast<std::uint64_t>(k));
    ParameterSet set;
    set.index = k;
    for (std::size_t i = 0; i < randomisation.parameters.size(); ++i) {
      const ParameterDistribution& distribution = randomisation.parameters[i];
      set.values.emplace_back(distribution.path, Draw(distribution, nominal_values[i], stream));
    }
    const auto files = static_cast<std::uint64_t>(randomisation.parameter_files.size());
    if (files > 0) {
      set.parameter_file = static_cast<int>(randomisation.files_in_sequence ? static_cast<std::uint64_t>(k) % files
                                                                            : stream.UniformInt(files));
    }
    const StartPoseRandomisation& pose = randomisation.start_pose;
    for (int axis = 0; axis < 3; ++axis) {
      // Up only along y: a drop is a start pose, a start inside the floor is not.
      const double low = axis == 1 ? 0.0 : -pose.position[axis];
      set.position_offset[axis] = stream.Uniform(low, pose.position[axis]);
    }
    set.yaw_degrees = stream.Uniform(-pose.yaw_degrees, pose.yaw_degrees);
    set.motor_angles_degrees = DrawMotorAngles(pose.motor_angle_degrees, motors, stream);
    sets.push_back(std::move(set));
  }
  return sets;
}

}  // namespace orcs::scene
