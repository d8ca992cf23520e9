#include "hardware/robot/joint_map.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string_view>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::hardware {
namespace {

/// The highest servo id a joint may have: 253 is reserved in Protocol 2.0 and 254 is the broadcast id.
constexpr int kMaxServoId = 252;

/// How far (in ticks) a limit may be past the servo's rated range through rounding of ticks_per_degree.
constexpr double kTickTolerance = 1e-6;

struct ServoName {
  std::string_view name;
  const dynamixel::ControlTable* table;
};
constexpr ServoName kServoNames[] = {{"AX-12+", &dynamixel::kAx12},
                                     {"AX-12", &dynamixel::kAx12},
                                     {"XL330-M288", &dynamixel::kXl330},
                                     {"XL330", &dynamixel::kXl330}};

dynamixel::ControlTable ParseServo(const JsonNode& node) {
  const std::string name = node.String("a servo model name");
  std::string known;
  for (const ServoName& servo : kServoNames) {
    if (servo.name == name) return *servo.table;
    known += (known.empty() ? "" : ", ") + text::Quote(servo.name);
  }
  node.Fail("a known servo model (" + known + ")", text::Quote(name));
}

/// The servo position (unrounded ticks) of a joint angle: ToTicks before rounding.
double ExactTicks(const JointMapping& m, double joint_deg) {
  return static_cast<double>(m.center_tick) +
         m.ticks_per_degree * (static_cast<double>(m.direction) * joint_deg + m.zero_offset_deg);
}

/// A limit must lie within the servo's rated range: ticks 0…max_tick + 1 before rounding, i.e. the whole 300° of an
/// AX-12+ (0…1023 covers 0°…300°) or 360° of an XL330. The rated edge (+150° on an AX-12+) is tick max_tick + 1.
void CheckLimitInRange(const JsonNode& node, const JointMapping& m, double joint_deg,
                       const dynamixel::ControlTable& servo) {
  const double ticks = ExactTicks(m, joint_deg);
  const double top = static_cast<double>(servo.max_tick) + 1.0;
  if (ticks >= -kTickTolerance && ticks <= top + kTickTolerance) return;
  const double low = ToDegrees(m, 0);
  const double high = ToDegrees(m, servo.max_tick + 1);
  node.Fail("a joint angle within the " + std::string(servo.name) + "'s range at this direction, offset and centre (" +
                text::FormatSignificant(std::min(low, high), 6) + "…" +
                text::FormatSignificant(std::max(low, high), 6) + "°, ticks 0…" + std::to_string(servo.max_tick) + ")",
            text::FormatDouble(joint_deg) + "° (tick " + text::FormatSignificant(ticks, 6) + ")");
}

JointMapping ParseJoint(const JsonNode& node, const dynamixel::ControlTable& servo) {
  node.ExpectOnly({"joint", "id", "direction", "zero_offset_deg", "ticks_per_degree", "center_tick", "min_deg",
                   "max_deg", "max_torque"});
  JointMapping m;
  const JsonNode joint = node.At("joint");
  m.joint = joint.String("the motor's name in the robot model");
  if (m.joint.empty()) joint.Fail("the motor's name in the robot model", "an empty string");

  const JsonNode id = node.At("id");
  const int id_value = id.Integer("a servo id 0…252");
  if (id_value < 0 || id_value > kMaxServoId) {
    id.Fail("a servo id 0…252 (253 is reserved, 254 is the broadcast id)", std::to_string(id_value));
  }
  m.id = static_cast<std::uint8_t>(id_value);

  if (node.Has("direction")) {
    const JsonNode direction = node.At("direction");
    m.direction = direction.Integer("a direction, 1 or -1");
    if (m.direction != 1 && m.direction != -1) direction.Fail("a direction, 1 or -1", std::to_string(m.direction));
  }
  m.zero_offset_deg = node.NumberOr("zero_offset_deg", 0.0, "a zero offset in servo degrees");

  m.ticks_per_degree = 1.0 / servo.degrees_per_tick;
  if (node.Has("ticks_per_degree")) {
    const JsonNode ticks = node.At("ticks_per_degree");
    m.ticks_per_degree = ticks.Number("a positive number of ticks per degree");
    if (!(m.ticks_per_degree > 0.0)) ticks.Fail("a positive number of ticks per degree");
  }
  m.center_tick = servo.center_tick;
  if (node.Has("center_tick")) {
    const JsonNode center = node.At("center_tick");
    const std::string what = "a centre tick 0…" + std::to_string(servo.max_tick);
    m.center_tick = center.Integer(what);
    if (m.center_tick < 0 || m.center_tick > servo.max_tick) center.Fail(what, std::to_string(m.center_tick));
  }

  const JsonNode min_deg = node.At("min_deg");
  const JsonNode max_deg = node.At("max_deg");
  m.min_deg = min_deg.Number("the lowest joint angle in degrees");
  m.max_deg = max_deg.Number("the highest joint angle in degrees");
  if (!(m.min_deg < m.max_deg)) {
    max_deg.Fail("a max_deg above min_deg (" + text::FormatDouble(m.min_deg) + ")", text::FormatDouble(m.max_deg));
  }
  CheckLimitInRange(min_deg, m, m.min_deg, servo);
  CheckLimitInRange(max_deg, m, m.max_deg, servo);

  if (node.Has("max_torque")) {
    const JsonNode torque = node.At("max_torque");
    const std::string what = "a torque limit in (0, 1], a fraction of the servo's maximum";
    m.max_torque = torque.Number(what);
    if (!(m.max_torque > 0.0 && m.max_torque <= 1.0)) torque.Fail(what, text::FormatDouble(m.max_torque));
  }
  return m;
}

}  // namespace

const JointMapping* JointMap::Find(const std::string& joint) const {
  const auto it = std::find_if(joints.begin(), joints.end(), [&](const JointMapping& m) { return m.joint == joint; });
  return it == joints.end() ? nullptr : &*it;
}

JointMap ParseJointMap(const nlohmann::json& j, const std::string& source) {
  if (!j.is_object()) throw InputError(source, 0, "expected a joint map (a JSON object), found " + DescribeJson(j));
  const JsonNode root(j, "", source);
  root.ExpectOnly({"agent", "servo", "baud", "joints"});
  JointMap map;
  map.source = source;
  const JsonNode agent = root.At("agent");
  map.agent = agent.String("the robot model's agent name");
  if (map.agent.empty()) agent.Fail("the robot model's agent name", "an empty string");
  map.servo = ParseServo(root.At("servo"));
  const JsonNode baud = root.At("baud");
  map.baud = baud.Integer("a positive baud rate (bits per second)");
  if (map.baud <= 0) baud.Fail("a positive baud rate (bits per second)", std::to_string(map.baud));

  const JsonNode joints = root.At("joints");
  const std::vector<JsonNode> elements = joints.Elements();
  if (elements.empty()) joints.Fail("at least one joint", "an empty array");
  for (std::size_t i = 0; i < elements.size(); ++i) {
    JointMapping m = ParseJoint(elements[i], map.servo);
    for (std::size_t k = 0; k < map.joints.size(); ++k) {
      const std::string other = elements[k].path() + " (" + text::Quote(map.joints[k].joint) + ")";
      if (map.joints[k].id == m.id) {
        elements[i].At("id").Fail("an id no other joint uses", std::to_string(m.id) + ", the id of " + other + " too");
      }
      if (map.joints[k].joint == m.joint) {
        elements[i].At("joint").Fail("a joint no other entry maps", text::Quote(m.joint) + ", mapped by " +
                                                                          elements[k].path() + " too");
      }
    }
    map.joints.push_back(std::move(m));
  }
  return map;
}

JointMap ReadJointMap(const std::string& path) { return ParseJointMap(ParseJson(ReadTextFile(path), path), path); }

std::int64_t ToTicks(const JointMapping& m, double joint_deg) {
  return static_cast<std::int64_t>(m.center_tick) +
         std::llround(m.ticks_per_degree * (static_cast<double>(m.direction) * joint_deg + m.zero_offset_deg));
}

double ToDegrees(const JointMapping& m, std::int64_t ticks) {
  const double servo_deg = static_cast<double>(ticks - m.center_tick) / m.ticks_per_degree;
  return static_cast<double>(m.direction) * (servo_deg - m.zero_offset_deg);
}

double ClampToLimits(const JointMapping& m, double joint_deg) { return std::clamp(joint_deg, m.min_deg, m.max_deg); }

}  // namespace orcs::hardware
