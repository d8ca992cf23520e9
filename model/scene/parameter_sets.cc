#include "model/scene/parameter_sets.h"

#include <algorithm>
#include <cmath>

#include "model/core/error.h"
#include "model/core/path_pattern.h"
#include "model/core/random_stream.h"
#include "model/core/text.h"

namespace orcs::scene {
namespace {

bool IsNumber(const Value& value) { return value.type() == ValueType::kDouble || value.type() == ValueType::kInt; }

double NumberOf(const Value& value) {
  return value.type() == ValueType::kDouble ? value.as_double() : static_cast<double>(value.as_int());
}

// One drawn quantity: a path, its distribution and its nominal value.
struct Varied {
  std::string path;
  const ParameterDistribution* distribution;
  double nominal;
};

// Each distribution's paths — its own, or every number its `match` names, in registration order — checked
// against the nominal world.
std::vector<Varied> VariedPaths(const Randomisation& randomisation, const VariableRepository& nominal,
                                const std::string& source) {
  std::vector<Varied> varied;
  for (std::size_t i = 0; i < randomisation.parameters.size(); ++i) {
    const ParameterDistribution& distribution = randomisation.parameters[i];
    const std::string field = "field 'randomisation.parameters[" + std::to_string(i) + "]." +
                              (distribution.match.empty() ? "path" : "match") + "' ";
    if (!distribution.match.empty()) {
      std::vector<int> ids;
      try {
        ids = nominal.Match(distribution.match);
      } catch (const InputError& error) {
        throw InputError(source, 0, field + error.what());
      }
      const std::size_t before = varied.size();
      for (int id : ids) {
        if (IsNumber(nominal.value(id))) varied.push_back({nominal.path(id), &distribution, NumberOf(nominal.value(id))});
      }
      if (varied.size() == before) {
        throw InputError(source, 0, field + "expected a pattern naming numbers of the world, found none matching " +
                                        text::Quote(distribution.match));
      }
      continue;
    }
    const Value* value = nominal.Find(distribution.path);
    if (value == nullptr) throw InputError(source, 0, field + "names an unknown repository path " + text::Quote(distribution.path));
    if (!IsNumber(*value)) {
      throw InputError(source, 0, field + "expected the path of a number, found '" + distribution.path +
                                      "' holding " + value->ToString());
    }
    varied.push_back({distribution.path, &distribution, NumberOf(*value)});
  }
  if (varied.size() * static_cast<std::size_t>(randomisation.sets) > kMaxDrawnValues) {
    throw InputError(source, 0, "field 'randomisation.parameters' expected at most " + std::to_string(kMaxDrawnValues) +
                                    " drawn values per job (sets × varied numbers), found " +
                                    std::to_string(randomisation.sets) + " × " + std::to_string(varied.size()));
  }
  return varied;
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

int AbsoluteDrawOf(const Randomisation& randomisation, const std::string& path) {
  for (std::size_t i = 0; i < randomisation.parameters.size(); ++i) {
    const ParameterDistribution& distribution = randomisation.parameters[i];
    if (distribution.relative) continue;
    if (distribution.match.empty() ? distribution.path == path : PathPattern(distribution.match).Matches(path)) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::vector<ParameterSet> DrawParameterSets(const Randomisation& randomisation, std::uint64_t seed,
                                            const VariableRepository& nominal,
                                            const std::vector<aseries::MorphologyMotor>& motors,
                                            const std::string& source) {
  const std::vector<Varied> varied = VariedPaths(randomisation, nominal, source);
  std::vector<ParameterSet> sets;
  for (int k = 0; k < randomisation.sets; ++k) {
    RandomStream stream(seed, "parameter-set", static_cast<std::uint64_t>(k));
    ParameterSet set;
    set.index = k;
    for (const Varied& v : varied) set.values.emplace_back(v.path, Draw(*v.distribution, v.nominal, stream));
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
