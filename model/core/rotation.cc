#include "model/core/rotation.h"

#include <algorithm>
#include <cmath>

namespace orcs {

Eigen::Quaterniond QuaternionFromEulerDegrees(const Eigen::Vector3d& angles_degrees) {
  const Eigen::Vector3d a = angles_degrees / kDegreesPerRadian;
  return Eigen::Quaterniond(Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()));
}

Eigen::Vector3d EulerDegreesFromQuaternion(const Eigen::Quaterniond& rotation) {
  const Eigen::Quaterniond q = rotation.normalized();
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  const double roll = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return Eigen::Vector3d(roll, pitch, yaw) * kDegreesPerRadian;
}

}  // namespace orcs
