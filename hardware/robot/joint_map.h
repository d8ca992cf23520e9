// A robot's joint map (issue 51): which Dynamixel servo drives which joint of the robot model, and how a joint
// angle becomes a servo tick — direction, zero offset, resolution, centre, limits and torque limit. Read from a
// JSON file (docs/hardware.md, "Joint maps"); every error names the file and the field.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hardware/dynamixel/control_table.h"

namespace orcs::hardware {

/// One joint of the robot and the servo that drives it.
struct JointMapping {
  std::string joint;              ///< the motor's name in the robot model ("Right/Knee", "Motor")
  std::uint8_t id = 0;            ///< the servo's id on the bus (0…252)
  int direction = 1;              ///< +1: the servo's ticks grow with the joint angle; −1: against it
  double zero_offset_deg = 0.0;   ///< servo degrees from the servo's centre tick to the joint's 0°
  double ticks_per_degree = 0.0;  ///< position resolution (1024/300 for an AX-12+, 4096/360 for an XL330)
  std::int32_t center_tick = 0;   ///< the servo's centre tick (512 AX-12+, 2048 XL330)
  double min_deg = 0.0;           ///< lowest joint angle that may be commanded, joint degrees
  double max_deg = 0.0;           ///< highest, joint degrees
  double max_torque = 1.0;        ///< torque limit, fraction 0…1 of the servo's maximum (written to its Torque Limit)
};

/// A robot's joint map: which servo drives which joint, and how.
struct JointMap {
  std::string source;                       ///< the file, for messages
  std::string agent;                        ///< the robot model's agent ("Humanoid", "Pendulum")
  dynamixel::ControlTable servo;            ///< the servo model (kAx12 or kXl330, by its "servo" name)
  int baud = 1000000;                       ///< bits per second of the bus
  std::vector<JointMapping> joints;         ///< in the file's order (the robot's motor order)
  const JointMapping* Find(const std::string& joint) const;  ///< nullptr when absent
};

/// A joint map from parsed JSON. Throws a one-line InputError "source: field 'joints[3].id' expected ..., found ..."
/// for unknown keys, an unknown servo, an id outside 0…252 or used twice, a joint named twice, a direction other than
/// ±1, min_deg ≥ max_deg, max_torque outside (0, 1], a limit outside the servo's position range, a baud rate that is
/// not positive, or no joints.
JointMap ParseJointMap(const nlohmann::json& j, const std::string& source);

/// ParseJointMap of the file at `path` (read through ReadTextFile, so bounded; messages name `path`).
JointMap ReadJointMap(const std::string& path);

/// The servo's goal tick for a joint angle (degrees), NOT clamped:
/// tick = center_tick + round(ticks_per_degree · (direction · joint_deg + zero_offset_deg)).
/// A limit at the very edge of the servo's rated range (+150° on an AX-12+ at offset 0) gives max_tick + 1: whoever
/// writes the tick to a servo clamps it to 0…max_tick.
std::int64_t ToTicks(const JointMapping& m, double joint_deg);

/// The joint angle (degrees) of a servo tick: the inverse of ToTicks (without the rounding).
double ToDegrees(const JointMapping& m, std::int64_t ticks);

/// The angle clamped to [min_deg, max_deg].
double ClampToLimits(const JointMapping& m, double joint_deg);

}  // namespace orcs::hardware
