// Raw ↔ normalised mapping of the A-Series agent interface values (spec/aseries.md §4d). The mapping is linear,
// raw = raw_min + (raw_max − raw_min)·(n − norm_min)/(norm_max − norm_min), and values are clamped to their
// range, as the original clamps every interface value when it is set.
#pragma once

#include <algorithm>
#include <string_view>

namespace orcs::aseries {

struct ValueRange {
  double raw_min;   ///< lowest raw value (raw unit of the value)
  double raw_max;   ///< highest raw value
  double norm_min;  ///< normalised value of raw_min
  double norm_max;  ///< normalised value of raw_max

  /// The raw value of normalised `n`; `n` outside [norm_min, norm_max] gives the nearest range end.
  constexpr double ToRaw(double n) const {
    const double raw = raw_min + (raw_max - raw_min) * (n - norm_min) / (norm_max - norm_min);
    return ClampRaw(raw);
  }
  /// The normalised value of `raw`; `raw` outside [raw_min, raw_max] gives the nearest range end.
  constexpr double ToNormalised(double raw) const {
    return norm_min + (norm_max - norm_min) * (ClampRaw(raw) - raw_min) / (raw_max - raw_min);
  }
  /// `raw` clamped to [raw_min, raw_max].
  constexpr double ClampRaw(double raw) const { return std::clamp(raw, raw_min, raw_max); }
};

/// <motor>/DesiredAngle: degrees, ±150 ↔ ±1, default 0.
inline constexpr ValueRange kDesiredAngleRange{-150.0, 150.0, -1.0, 1.0};
/// <motor>/DesiredTorque: fraction of the maximum torque, −1…1 ↔ 0…1 ("EliminateNegativeTorqueRange"), so
/// raw = 2n − 1 and a normalised torque ≤ 0.5 gives no motor torque after max(0, ·) (spec §4d, §6c).
inline constexpr ValueRange kDesiredTorqueRange{-1.0, 1.0, 0.0, 1.0};
/// <motor>/JointAngle: degrees, ±150 ↔ ±1.
inline constexpr ValueRange kJointAngleRange{-150.0, 150.0, -1.0, 1.0};
/// <board>/AccelAxis1, AccelAxis2: m/s², ±16.072704 (±1.6384 g) ↔ ±1, default 0.
inline constexpr ValueRange kAccelAxisRange{-16.072704, 16.072704, -1.0, 1.0};

/// Default raw DesiredTorque of every motor (normalised 0.7934), spec §4d.
inline constexpr double kDefaultDesiredTorqueRaw = 0.586810005;

/// The range of an agent interface value by its name's last part ("…/Right/Knee/DesiredAngle"), or nullptr
/// for values that have no normalised form (positions, parameters).
inline const ValueRange* InterfaceRangeOf(std::string_view path) {
  const auto ends_with = [path](std::string_view suffix) {
    return path.size() >= suffix.size() && path.substr(path.size() - suffix.size()) == suffix;
  };
  if (ends_with("/DesiredAngle")) return &kDesiredAngleRange;
  if (ends_with("/DesiredTorque")) return &kDesiredTorqueRange;
  if (ends_with("/JointAngle")) return &kJointAngleRange;
  if (ends_with("/AccelAxis1") || ends_with("/AccelAxis2")) return &kAccelAxisRange;
  return nullptr;
}

}  // namespace orcs::aseries
