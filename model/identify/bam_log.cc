#include "model/identify/bam_log.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"

namespace orcs::identify {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

// 12 significant digits: a degree to 1e-10 at most, far below any encoder, and enough that a log converted from
// 9-digit degrees to radians reads back as the same degrees (the radians' last bit rounds away).
std::string Degrees(double radians) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g", radians * kDegreesPerRadian);
  return buffer;
}

std::string Plain(double value) { return text::FormatDouble(value); }

// The rig's constants as the XL330 CSVs' first comment line names them (key=value, the keys the log has).
std::string RigComment(const JsonNode& root) {
  struct Key {
    const char* json;   // BAM's key
    const char* table;  // the comment's key
    bool is_number;     // a number (else a string)
  };
  static constexpr Key kKeys[] = {{"motor", "motor", false},          {"mass", "load_mass_kg", true},
                                  {"length", "load_distance_m", true}, {"kp", "firmware_kp", true},
                                  {"vin", "supply_v", true},           {"dt", "dt_s", true},
                                  {"trajectory", "trajectory", false}};
  std::string comment = "# BAM log:";
  for (const Key& key : kKeys) {
    if (!root.Has(key.json)) continue;
    const JsonNode node = root.At(key.json);
    std::string value = key.is_number ? Plain(node.Number("a number")) : node.String("a name");
    if (value.find_first_of(" \t\r\n") != std::string::npos) {
      throw InputError(root.source(), 0,
                       "field '" + std::string(key.json) + "' expected a name without blanks, found " +
                           text::Quote(value));
    }
    comment += " " + std::string(key.table) + "=" + value;
  }
  return comment + "\n";
}

std::string Row(const JsonNode& entry, double first_timestamp) {
  std::string row = Plain(entry.At("timestamp").Number("a time in seconds") - first_timestamp);
  row += "," + Degrees(entry.At("goal_position").Number("an angle in radians"));
  row += "," + Degrees(entry.At("position").Number("an angle in radians"));
  row += "," + Degrees(entry.At("speed").Number("a speed in radians per second"));
  row += "," + Plain(entry.At("load").Number("a number"));
  row += "," + Plain(entry.At("input_volts").Number("a voltage"));
  row += "," + Plain(entry.At("temp").Number("a temperature in °C"));
  row += entry.At("torque_enable").Bool("true or false") ? ",1\n" : ",0\n";
  return row;
}

}  // namespace

bool IsBamLog(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  return first != std::string_view::npos && text[first] == '{';
}

std::string BamLogAsTable(std::string_view json_text, const std::string& source) {
  const nlohmann::json j = ParseJson(std::string(json_text), source);
  if (!j.is_object()) throw InputError(source, 0, "expected a BAM log (a JSON object), found " + DescribeJson(j));
  const JsonNode root(j, "", source);
  const std::vector<JsonNode> entries = root.At("entries").Elements();
  if (entries.empty()) throw InputError(source, 0, "field 'entries' expected at least one entry, found none");
  const double first_timestamp = entries.front().At("timestamp").Number("a time in seconds");
  std::string table = RigComment(root);
  table += "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n";
  for (const JsonNode& entry : entries) table += Row(entry, first_timestamp);
  return table;
}

ColumnMapping BamLogMapping(std::string_view table, const std::string& source) {
  const auto column = [](const char* name) {
    ColumnSource source_column;
    source_column.column = name;
    return source_column;
  };
  ColumnMapping mapping;
  mapping.source = source + " (BAM's log, read as a pendulum servo)";
  mapping.agent = "Pendulum";
  mapping.time = column("time_s");
  mapping.channels.push_back(ChannelMapping{.motor = "Motor",
                                            .desired_angle = column("goal_deg"),
                                            .desired_torque = column("torque_enable"),
                                            .joint_angle = column("position_deg")});
  const std::string_view rig = table.substr(0, table.find('\n'));
  if (rig.find(" firmware_kp=") != std::string_view::npos) {
    mapping.firmware_kp.emplace();
    mapping.firmware_kp->header = "firmware_kp";
  }
  mapping.supply_voltage = column("input_volts");
  mapping.command_timing = CommandTiming::kFromRow;
  return mapping;
}

}  // namespace orcs::identify
