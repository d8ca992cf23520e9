// Orientation conventions at the interfaces: the original's Euler angle triple (α, β, γ) in degrees means
// R = Rz(γ)·Ry(β)·Rx(α) (spec/aseries.md §1). Inside, orientations are unit quaternions.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace orcs {

/// Quaternion of the Euler triple (α, β, γ) in degrees, R = Rz(γ)·Ry(β)·Rx(α).
Eigen::Quaterniond QuaternionFromEulerDegrees(const Eigen::Vector3d& angles_degrees);

/// The Euler triple (α, β, γ) in degrees of a rotation, with β in [−90, 90]; inverse of the above away from
/// β = ±90°.
Eigen::Vector3d EulerDegreesFromQuaternion(const Eigen::Quaterniond& rotation);

constexpr double kDegreesPerRadian = 57.29577951308232;
constexpr double DegreesToRadians(double degrees) { return degrees / kDegreesPerRadian; }
constexpr double RadiansToDegrees(double radians) { return radians * kDegreesPerRadian; }

}  // namespace orcs
