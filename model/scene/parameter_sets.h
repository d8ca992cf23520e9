// Drawing a job's K parameter sets (docs/scenarios.md, "randomisation") from the job's seed alone: set k uses
// the stream RandomStream(seed, "parameter-set", k) and draws, in this order, every varied parameter in the
// scenario's order, the value file (when chosen at random), the start-pose offsets, the initial motor angles. The same seed gives the
// same sets on any machine, in any order, at any worker count. The initial motor angles come last and are drawn
// only when randomised, so sets without them keep the bits they had before motor angles existed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "model/aseries/aseries_morphology.h"
#include "model/core/variable_repository.h"
#include "model/scene/scenario.h"

namespace orcs::scene {

/// One drawn parameter set.
struct ParameterSet {
  int index = 0;                                            ///< k, 0…K−1
  std::vector<std::pair<std::string, double>> values;       ///< drawn repository values, path → value
  int parameter_file = -1;                                  ///< index into Randomisation::parameter_files, −1 = none
  Eigen::Vector3d position_offset = Eigen::Vector3d::Zero();  ///< agent start offset, m
  double yaw_degrees = 0.0;                                 ///< agent start turn about the vertical, degrees
  /// Initial angle of each of the agent's motors, motor order, degrees, within the motor's range; empty when the
  /// motor angles are not randomised (they start at 0, the initial pose).
  std::vector<double> motor_angles_degrees;
};

/// Draws `randomisation.sets` parameter sets. `nominal` is the repository after the scenario's values: it gives
/// the nominal value of relative distributions and checks that every varied path exists and is a number.
/// `motors` are the scenario agent's motors (its morphology's, motor order): with start_pose.motor_angle_degrees
/// a > 0, each set draws one angle per motor, uniform in [−a, +a], then clamped to the motor's min…max degrees.
/// Throws InputError naming the scenario field for an unknown or non-numeric path.
std::vector<ParameterSet> DrawParameterSets(const Randomisation& randomisation, std::uint64_t seed,
                                            const VariableRepository& nominal,
                                            const std::vector<aseries::MorphologyMotor>& motors,
                                            const std::string& source);

/// The index of the distribution of `randomisation` that draws `path` anew and not relative to its nominal value
/// (its `path`, or a `match` naming it), or −1: a value set on such a path (a sweep, --set) is replaced by every
/// parameter set's draw.
int AbsoluteDrawOf(const Randomisation& randomisation, const std::string& path);

}  // namespace orcs::scene
