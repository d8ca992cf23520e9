#include "model/identify/measured_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>
#include <utility>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"
#include "model/identify/bam_log.h"

namespace orcs::identify {
namespace {

constexpr double kTimeZeroTolerance = 1e-9;      // s: the first row's time counts as 0 within this
constexpr double kStepRelativeTolerance = 1e-6;  // of the step: how far one row's step may differ from the first
constexpr double kStepAgreeTolerance = 1e-9;     // s: two runs' steps count as the same within this
constexpr char kNativeDelimiter = ',';
constexpr std::string_view kColumnsKey = "columns:";
constexpr std::string_view kSimPrefix = "/Sim/";
constexpr std::string_view kDesiredAngle = "DesiredAngle";
constexpr std::string_view kDesiredTorque = "DesiredTorque";
constexpr std::string_view kJointAngle = "JointAngle";
constexpr std::string_view kFirmwareKpColumn = "/Servo/FirmwareKp";  // an orcs log's column of the servo's gain
constexpr std::string_view kWindingTemperatureColumn = "/Servo/WindingTemperature";  // and of its temperature, °C
constexpr std::string_view kSupplyVoltageColumn = "/Servo/SupplyVoltage";  // and of its supply voltage, V
constexpr double kMaxSupplyVoltage = 60.0;  // V: above any hobby servo's supply; a log in mV would be far off

std::string Seconds(double value) { return text::FormatDouble(value) + " s"; }

// A computed step (a difference of two times) for messages: 12 significant digits, so that rounding noise of
// the subtraction (0.019999999999999997) does not show while 1e-9 s differences between runs still do.
std::string StepSeconds(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g s", value);
  return buffer;
}

// ---------------------------------------------------------------------------------------------------------
// Lines and fields

// One line of the input, without its line break.
struct Line {
  int number = 0;         // 1-based line number
  std::string_view text;  // without '\r' and, on line 1, without a UTF-8 byte order mark
};

std::vector<Line> SplitLines(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // spreadsheet exports start with a BOM
  std::vector<Line> lines;
  int number = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    std::string_view content = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
    if (!content.empty() && content.back() == '\r') content.remove_suffix(1);
    lines.push_back({++number, content});
  }
  return lines;
}

bool IsBlank(std::string_view line) { return text::Trim(line).empty(); }
bool IsComment(std::string_view line) {
  const std::string_view trimmed = text::Trim(line);
  return !trimmed.empty() && trimmed.front() == '#';
}

// The quoted field whose opening quote is at line[open] ("" inside stands for one quote); `close` receives the
// index of the closing quote.
std::string ReadQuoted(std::string_view line, size_t open, size_t& close, const std::string& source, int number) {
  std::string field;
  for (size_t i = open + 1; i < line.size(); ++i) {
    if (line[i] != '"') {
      field += line[i];
    } else if (i + 1 < line.size() && line[i + 1] == '"') {
      field += '"';
      ++i;
    } else {
      close = i;
      return field;
    }
  }
  throw InputError(source, number, "field " + text::Quote(line.substr(open)) + " has no closing quote");
}

// The fields of a row or header, trimmed; a field in double quotes (RFC 4180) may hold the delimiter and is
// returned without its quotes.
std::vector<std::string> SplitFields(std::string_view line, char delimiter, const std::string& source, int number) {
  std::vector<std::string> fields;
  size_t pos = 0;
  while (true) {
    size_t next = line.find(delimiter, pos);
    const std::string_view field = text::Trim(line.substr(pos, next == std::string_view::npos ? next : next - pos));
    if (!field.empty() && field.front() == '"') {
      size_t close = 0;
      fields.push_back(ReadQuoted(line, static_cast<size_t>(field.data() - line.data()), close, source, number));
      next = line.find(delimiter, close + 1);
      const std::string_view after = line.substr(close + 1, next == std::string_view::npos ? next : next - close - 1);
      if (!IsBlank(after)) {
        throw InputError(source, number, "text " + text::Quote(after) + " after the closing quote of a field");
      }
    } else {
      fields.emplace_back(field);
    }
    if (next == std::string_view::npos) return fields;
    pos = next + 1;
  }
}

// ---------------------------------------------------------------------------------------------------------
// The table: column names and data rows

struct Table {
  std::vector<std::string> columns;  // column names, trimmed and unquoted
  std::vector<Line> rows;            // data rows; blank and comment lines left out
  std::vector<Line> comments;        // the '#' comment lines, for header keys ("# ... firmware_kp=400")
};

// The column list of a "# columns: a,b,c" comment, or nullopt for any other comment.
std::optional<std::string_view> ColumnsComment(std::string_view line) {
  std::string_view body = text::Trim(line);
  body = text::Trim(body.substr(1));  // after '#'
  if (text::ToLower(body.substr(0, kColumnsKey.size())) != kColumnsKey) return std::nullopt;
  return text::Trim(body.substr(kColumnsKey.size()));
}

// A comment of an orcs log: the "# columns:" one becomes the header (once, before the first data row).
void NoteComment(const Line& line, std::optional<Line>& header, const std::vector<Line>& rows,
                 const std::string& source) {
  const std::optional<std::string_view> columns = ColumnsComment(line.text);
  if (!columns) return;
  if (header) {
    throw InputError(source, line.number,
                     "a second '# columns:' comment (the first is on line " + std::to_string(header->number) + ")");
  }
  if (!rows.empty()) {
    throw InputError(source, line.number,
                     "'# columns:' comes after the first data row (line " + std::to_string(rows.front().number) +
                         "); it must name the columns before them");
  }
  header = Line{line.number, *columns};
}

// Splits the text into header and rows: the header is the "# columns:" comment (orcs log) or, with a mapping,
// the first line that is neither blank nor a comment.
Table ReadTable(std::string_view text, const std::string& source, const ColumnMapping* mapping) {
  Table table;
  std::optional<Line> header;
  for (const Line& line : SplitLines(text)) {
    if (IsBlank(line.text)) continue;
    if (IsComment(line.text)) {
      table.comments.push_back(line);
      if (!mapping) NoteComment(line, header, table.rows, source);
    } else if (mapping && !header) {
      header = line;
    } else {
      table.rows.push_back(line);
    }
  }
  if (table.rows.empty()) throw InputError(source, 0, "no data rows");
  if (!header) {
    throw InputError(source, 0,
                     "no '# columns:' comment naming the columns (orcs-sim logs have one; other CSVs need a "
                     "column mapping)");
  }
  if (table.rows.size() < 2) {
    throw InputError(source, 0, "expected at least 2 data rows (a time step needs two times), found 1");
  }
  table.columns = SplitFields(header->text, mapping ? mapping->delimiter : kNativeDelimiter, source, header->number);
  return table;
}

// ---------------------------------------------------------------------------------------------------------
// Plans: which field of a row fills which series of the run

// Where one series of the run comes from.
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

struct SeriesSource {
  std::string column;                     // column name, for messages
  int field = -1;                         // index of the field in a row; −1: every row is `constant`
  double scale = 1.0;                     // value = raw · scale + offset
  double offset = 0.0;
  double constant = 0.0;                  // the value when field is −1
  std::vector<double>* values = nullptr;  // the run's series it fills
  double max_magnitude = kUnbounded;      // a larger |value| is not a measurement
  // A mapped goal: an empty cell is a limp row if this plan entry (its motor's torque) says 0 there; −1 = never
  int limp_torque = -1;
};

// A joint angle (measured or commanded) beyond ±360° is not a measurement of a hinge; such a value (1e308° in a
// careless export) must not reach the fitter (docs/gap_measured_data.md).
constexpr double kMaxAngleDegrees = 360.0;

std::vector<double>& SeriesOf(MeasuredRun& run, std::string_view quantity, const std::string& motor) {
  if (quantity == kDesiredAngle) return run.desired_angle[motor];
  if (quantity == kDesiredTorque) return run.desired_torque[motor];
  return run.joint_angle[motor];
}

// A column "/Sim/<agent>/<motor>/<quantity>" of an orcs log, quantity one of the three the gap needs.
struct MotorField {
  std::string agent;
  std::string motor;          // may hold '/' ("Right/Knee")
  std::string_view quantity;  // kDesiredAngle, kDesiredTorque or kJointAngle
  int field = 0;              // index in a row
};

std::optional<MotorField> ParseMotorColumn(std::string_view name, int field) {
  if (name.substr(0, kSimPrefix.size()) != kSimPrefix) return std::nullopt;
  const std::vector<std::string_view> parts = text::Split(name.substr(kSimPrefix.size()), '/');
  if (parts.size() < 3) return std::nullopt;
  if (std::any_of(parts.begin(), parts.end(), [](std::string_view part) { return part.empty(); })) {
    return std::nullopt;
  }
  const std::string_view quantity = parts.back();
  for (std::string_view known : {kDesiredAngle, kDesiredTorque, kJointAngle}) {
    if (quantity != known) continue;
    const std::string_view motor = name.substr(kSimPrefix.size() + parts[0].size() + 1);
    return MotorField{std::string(parts[0]), std::string(motor.substr(0, motor.size() - quantity.size() - 1)),
                      known, field};
  }
  return std::nullopt;
}

// An accelerometer column "/Sim/<agent>/<board>/AccelAxis1|2" of an orcs log: its agent and channel
// ("<board>/AccelAxisN").
struct AccelerometerField {
  std::string agent;
  std::string channel;
  int field = 0;
};

std::optional<AccelerometerField> ParseAccelerometerColumn(std::string_view name, int field) {
  if (name.substr(0, kSimPrefix.size()) != kSimPrefix) return std::nullopt;
  const std::vector<std::string_view> parts = text::Split(name.substr(kSimPrefix.size()), '/');
  if (parts.size() != 3 || parts[0].empty() || parts[1].empty()) return std::nullopt;
  if (parts[2] != "AccelAxis1" && parts[2] != "AccelAxis2") return std::nullopt;
  return AccelerometerField{std::string(parts[0]), std::string(parts[1]) + "/" + std::string(parts[2]), field};
}

// The accelerometer axes of a mapping or log must be a board's AccelAxis1 or AccelAxis2.
bool IsAccelerometerChannel(const std::string& channel) {
  const std::size_t slash = channel.find('/');
  if (slash == 0 || slash == std::string::npos || channel.find('/', slash + 1) != std::string::npos) return false;
  const std::string axis = channel.substr(slash + 1);
  return axis == "AccelAxis1" || axis == "AccelAxis2";
}

// Accelerometer readings beyond this are no reading of an ADXL213 (its range is ±1.7 g) nor of any board a robot
// carries: a careless export.
constexpr double kMaxAcceleration = 1000.0;

// The motor columns of an orcs log header, checked: one agent, no column twice.
std::vector<MotorField> MotorFields(const Table& table, const std::string& source) {
  std::vector<MotorField> fields;
  std::map<std::string_view, int> seen;  // motor column name → its field index
  for (size_t i = 1; i < table.columns.size(); ++i) {
    const std::string& name = table.columns[i];
    std::optional<MotorField> field = ParseMotorColumn(name, static_cast<int>(i));
    if (!field) continue;  // accelerometers, MotorTorque, ...: not needed here
    if (const auto [it, fresh] = seen.emplace(name, static_cast<int>(i)); !fresh) {
      throw InputError(source, 0,
                       "column " + text::Quote(name) + " appears twice (fields " + std::to_string(it->second + 1) + " and " +
                           std::to_string(i + 1) + ")");
    }
    if (!fields.empty() && field->agent != fields.front().agent) {
      throw InputError(source, 0, "columns of two agents, " + text::Quote(fields.front().agent) + " and " + text::Quote(field->agent));
    }
    fields.push_back(std::move(*field));
  }
  return fields;
}

bool HasField(const std::vector<MotorField>& fields, const std::string& motor, std::string_view quantity) {
  return std::any_of(fields.begin(), fields.end(),
                     [&](const MotorField& f) { return f.motor == motor && f.quantity == quantity; });
}

// run.motors and run.commanded from the motor columns; a motor with one input column but not the other is an
// error naming the missing one.
void ListMotors(const std::vector<MotorField>& fields, const std::string& source, MeasuredRun& run) {
  for (const MotorField& f : fields) {
    if (f.quantity == kJointAngle) {
      run.motors.push_back(f.motor);
      continue;
    }
    const std::string_view other = f.quantity == kDesiredAngle ? kDesiredTorque : kDesiredAngle;
    if (!HasField(fields, f.motor, other)) {
      throw InputError(source, 0,
                       "no column '" + MotorColumn(f.agent, f.motor, std::string(other)) + "' to go with '" +
                           MotorColumn(f.agent, f.motor, std::string(f.quantity)) +
                           "' (a commanded motor needs both)");
    }
    if (std::find(run.commanded.begin(), run.commanded.end(), f.motor) == run.commanded.end()) {
      run.commanded.push_back(f.motor);
    }
  }
  if (run.motors.empty()) throw InputError(source, 0, "no '/Sim/<agent>/<motor>/JointAngle' column");
}

std::vector<SeriesSource> NativePlan(const Table& table, const std::string& source, MeasuredRun& run) {
  if (table.columns.front() != "time") {
    throw InputError(source, 0, "expected the first column to be 'time', found " + text::Quote(table.columns.front()));
  }
  const std::vector<MotorField> fields = MotorFields(table, source);
  ListMotors(fields, source, run);
  run.agent = fields.front().agent;
  std::vector<SeriesSource> plan = {{"time", 0, 1.0, 0.0, 0.0, &run.time, kUnbounded}};
  for (const MotorField& f : fields) {
    plan.push_back({table.columns[f.field], f.field, 1.0, 0.0, 0.0, &SeriesOf(run, f.quantity, f.motor), kUnbounded});
    if (f.quantity != kDesiredTorque) plan.back().max_magnitude = kMaxAngleDegrees;
  }
  const auto run_input = [&](std::string_view column, std::string& name, std::vector<double>& values) {
    const auto found = std::find(table.columns.begin(), table.columns.end(), column);
    if (found == table.columns.end()) return;
    name = std::string(column);
    plan.push_back({name, static_cast<int>(found - table.columns.begin()), 1.0, 0.0, 0.0, &values, kUnbounded});
  };
  run_input(kFirmwareKpColumn, run.firmware_kp_column, run.firmware_kp);
  run_input(kWindingTemperatureColumn, run.winding_temperature_column, run.winding_temperature);
  run_input(kSupplyVoltageColumn, run.supply_voltage_column, run.supply_voltage);
  for (size_t i = 1; i < table.columns.size(); ++i) {
    const std::optional<AccelerometerField> accelerometer =
        ParseAccelerometerColumn(table.columns[i], static_cast<int>(i));
    if (!accelerometer || accelerometer->agent != run.agent) continue;
    if (run.acceleration.count(accelerometer->channel) != 0) {
      throw InputError(source, 0, "column " + text::Quote(table.columns[i]) + " appears twice");
    }
    run.accelerometers.push_back(accelerometer->channel);
    plan.push_back({table.columns[i], accelerometer->field, 1.0, 0.0, 0.0, &run.acceleration[accelerometer->channel],
                    kMaxAcceleration});
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------------------
// Column mappings

[[noreturn]] void FieldError(const std::string& source, const std::string& field, const std::string& expected,
                             const std::string& found) {
  throw InputError(source, 0, "field " + text::Quote(field) + " expected " + expected + ", found " + found);
}

std::string ChannelField(size_t index, std::string_view member = {}) {
  std::string field = "channels[" + std::to_string(index) + "]";
  return member.empty() ? field : field + "." + std::string(member);
}

// A source must be a column or a constant; `column_only` ones (time, joint angles) must be a column.
void CheckSource(const ColumnSource& s, const std::string& field, bool column_only, const std::string& source) {
  if (!s.header.empty()) FieldError(source, field + ".header", "a column or a constant", "a header key");
  if (column_only && s.constant) FieldError(source, field, "a column", "a constant");
  if (s.constant && !s.column.empty()) FieldError(source, field, "either a column or a constant", "both");
  if (!s.constant && text::Trim(s.column).empty()) FieldError(source, field, "a column or a constant", "neither");
  if (!std::isfinite(s.scale) || !std::isfinite(s.offset) || (s.constant && !std::isfinite(*s.constant))) {
    FieldError(source, field, "finite numbers", "a value that is not");
  }
}

void CheckChannel(const ColumnMapping& m, size_t i, std::set<std::string>& motors) {
  const ChannelMapping& c = m.channels[i];
  if (c.motor.empty() || c.motor.front() == '/' || c.motor.back() == '/') {
    FieldError(m.source, ChannelField(i, "motor"), "a motor name (e.g. \"Right/Knee\")", text::Quote(c.motor));
  }
  if (!motors.insert(c.motor).second) {
    FieldError(m.source, ChannelField(i, "motor"), "a motor not named before", text::Quote(c.motor));
  }
  if (c.desired_angle.has_value() != c.desired_torque.has_value()) {
    const char* missing = c.desired_angle ? "desired_torque" : "desired_angle";
    const char* given = c.desired_angle ? "desired_angle" : "desired_torque";
    FieldError(m.source, ChannelField(i, missing),
               std::string("a value, since '") + given + "' is given (a commanded motor needs both)",
               "nothing (the field is missing)");
  }
  if (c.desired_angle) CheckSource(*c.desired_angle, ChannelField(i, "desired_angle"), false, m.source);
  if (c.desired_torque) CheckSource(*c.desired_torque, ChannelField(i, "desired_torque"), false, m.source);
  if (c.joint_angle) CheckSource(*c.joint_angle, ChannelField(i, "joint_angle"), true, m.source);
}

// The rules a mapping must follow whether it was read from JSON or built in code.
void CheckMapping(const ColumnMapping& m) {
  if (m.agent.empty() || m.agent.find('/') != std::string::npos) {
    FieldError(m.source, "agent", "an agent name without '/'", text::Quote(m.agent));
  }
  if (m.delimiter == '"' || m.delimiter == '\n' || m.delimiter == '\r') {
    FieldError(m.source, "delimiter", "one character other than a quote or a line break",
               text::Quote(std::string(1, m.delimiter)));
  }
  CheckSource(m.time, "time", true, m.source);
  if (m.channels.empty()) FieldError(m.source, "channels", "at least one channel", "none");
  std::set<std::string> motors;
  for (size_t i = 0; i < m.channels.size(); ++i) CheckChannel(m, i, motors);
  if (std::none_of(m.channels.begin(), m.channels.end(), [](const ChannelMapping& c) { return c.joint_angle; })) {
    FieldError(m.source, "channels", "at least one channel with a 'joint_angle'", "none");
  }
  std::set<std::string> axes;
  for (size_t i = 0; i < m.accelerometers.size(); ++i) {
    const AccelerometerMapping& a = m.accelerometers[i];
    const std::string field = "accelerometers[" + std::to_string(i) + "]";
    if (!IsAccelerometerChannel(a.channel)) {
      FieldError(m.source, field + ".channel", "a board's axis (e.g. \"ABSR/AccelAxis1\")", text::Quote(a.channel));
    }
    if (!axes.insert(a.channel).second) {
      FieldError(m.source, field + ".channel", "an axis not named before", text::Quote(a.channel));
    }
    CheckSource(a.value, field, true, m.source);
    if (a.noise && !(*a.noise > 0.0 && std::isfinite(*a.noise))) {
      FieldError(m.source, field + ".noise", "a positive σ in m/s²", text::FormatDouble(*a.noise));
    }
  }
}

ColumnSource ParseColumnSource(const JsonNode& node) {
  node.ExpectOnly({"column", "scale", "offset", "constant", "header"});
  ColumnSource s;
  if (node.Has("column") && node.Has("constant")) node.Fail("either \"column\" or \"constant\"", "both");
  if (node.Has("header") && (node.Has("column") || node.Has("constant"))) {
    node.Fail("\"header\" alone, without \"column\" or \"constant\"", "both");
  }
  if (node.Has("header")) {
    s.header = std::string(text::Trim(node.At("header").String("a header key")));
    if (s.header.empty() || s.header.find_first_of(" =") != std::string::npos) node.At("header").Fail("a header key");
    for (const char* key : {"scale", "offset"}) {
      if (node.Has(key)) node.At(key).Fail("nothing beside \"header\"");
    }
    return s;
  }
  if (node.Has("constant")) {
    for (const char* key : {"scale", "offset"}) {
      if (node.Has(key)) node.At(key).Fail("nothing beside \"constant\"");
    }
    s.constant = node.At("constant").Number("a finite number");
    return s;
  }
  if (!node.Has("column")) node.Fail("an object with \"column\" or \"constant\"", "neither");
  s.column = std::string(text::Trim(node.At("column").String("a column name")));
  if (s.column.empty()) node.At("column").Fail("a column name");
  s.scale = node.NumberOr("scale", 1.0, "a finite number");
  s.offset = node.NumberOr("offset", 0.0, "a finite number");
  return s;
}

ChannelMapping ParseChannel(const JsonNode& node) {
  node.ExpectOnly({"motor", "desired_angle", "desired_torque", "joint_angle"});
  ChannelMapping c;
  c.motor = node.At("motor").String("a motor name");
  if (node.Has("desired_angle")) c.desired_angle = ParseColumnSource(node.At("desired_angle"));
  if (node.Has("desired_torque")) c.desired_torque = ParseColumnSource(node.At("desired_torque"));
  if (node.Has("joint_angle")) c.joint_angle = ParseColumnSource(node.At("joint_angle"));
  return c;
}

AccelerometerMapping ParseAccelerometer(const JsonNode& node) {
  node.ExpectOnly({"channel", "column", "scale", "offset", "noise"});
  AccelerometerMapping a;
  a.channel = std::string(text::Trim(node.At("channel").String("a board's axis, e.g. \"ABSR/AccelAxis1\"")));
  if (!node.Has("column")) node.Fail("an object with \"column\"", "none");
  a.value.column = std::string(text::Trim(node.At("column").String("a column name")));
  if (a.value.column.empty()) node.At("column").Fail("a column name");
  a.value.scale = node.NumberOr("scale", 1.0, "a finite number");
  a.value.offset = node.NumberOr("offset", 0.0, "a finite number");
  if (node.Has("noise")) a.noise = node.At("noise").Number("a positive σ in m/s²");
  return a;
}

char ParseDelimiter(const JsonNode& node) {
  const std::string delimiter = node.String("a one-character string");
  if (delimiter.size() != 1) node.Fail("a one-character string");
  return delimiter.front();
}

CommandTiming ParseCommandTiming(const JsonNode& node) {
  const std::string timing = node.String("\"until_row\" or \"from_row\"");
  if (timing == "until_row") return CommandTiming::kUntilRow;
  if (timing == "from_row") return CommandTiming::kFromRow;
  node.Fail("\"until_row\" (a row's commands produced its state) or \"from_row\" (they act after it)");
}

// The field index of a mapped column in the header; the column must be there exactly once.
int FieldOf(const Table& table, const std::string& column, const std::string& field, const std::string& mapping,
            const std::string& source) {
  const auto first = std::find(table.columns.begin(), table.columns.end(), column);
  if (first == table.columns.end()) {
    throw InputError(source, 0, "no column " + text::Quote(column) + " (named by " + mapping + ", field " + text::Quote(field) + ")");
  }
  const auto second = std::find(first + 1, table.columns.end(), column);
  if (second != table.columns.end()) {
    const auto number = [&](auto it) { return std::to_string(it - table.columns.begin() + 1); };
    throw InputError(source, 0,
                     "column " + text::Quote(column) + " appears twice (fields " + number(first) + " and " + number(second) +
                         "), so " + mapping + ", field " + text::Quote(field) + " is ambiguous");
  }
  return static_cast<int>(first - table.columns.begin());
}

SeriesSource MappedSeries(const ColumnSource& s, const std::string& field, const Table& table,
                          const ColumnMapping& m, const std::string& source, std::vector<double>& values) {
  if (s.constant) return {field, -1, 1.0, 0.0, *s.constant, &values, kUnbounded};
  return {s.column, FieldOf(table, s.column, field + ".column", m.source, source), s.scale, s.offset, 0.0, &values,
          kUnbounded};
}

// The value of `key` in the comment lines: the token "key=value" (tokens split at blanks).
std::optional<std::string> HeaderValue(const Table& table, const std::string& key) {
  const std::string prefix = key + "=";
  for (const Line& comment : table.comments) {
    for (std::string_view token : text::Split(text::Trim(comment.text.substr(1)), ' ')) {
      if (token.substr(0, prefix.size()) == prefix) return std::string(token.substr(prefix.size()));
    }
  }
  return std::nullopt;
}

// An input of the servo (its firmware gain, its winding temperature, its supply voltage) from a column, a constant or a header
// key; `field` is the mapping's field and `what` says what is missing.
SeriesSource RunInputSeries(const ColumnSource& s, const std::string& field, const std::string& what,
                            const Table& table, const ColumnMapping& m, const std::string& source,
                            std::vector<double>& values, std::string& column) {
  if (s.header.empty()) {
    SeriesSource series = MappedSeries(s, field, table, m, source, values);
    column = series.column;
    return series;
  }
  column = "header key " + text::Quote(s.header);
  const std::optional<std::string> value = HeaderValue(table, s.header);
  if (!value) {
    throw InputError(source, 0, "no '" + s.header + "=' in the comment lines (named by " + m.source + ", field '" +
                                    field + ".header'): " + what + " is missing");
  }
  const std::optional<double> number = text::ParseDouble(*value);
  if (!number || !std::isfinite(*number)) {
    throw InputError(source, 0, "header key " + text::Quote(s.header) + ": " + text::Quote(*value) + " is not a finite number");
  }
  return {column, -1, 1.0, 0.0, *number, &values, kUnbounded};
}

std::vector<SeriesSource> MappedPlan(const Table& table, const ColumnMapping& m, const std::string& source,
                                     MeasuredRun& run) {
  CheckMapping(m);
  run.agent = m.agent;
  std::vector<SeriesSource> plan = {MappedSeries(m.time, "time", table, m, source, run.time)};
  for (size_t i = 0; i < m.channels.size(); ++i) {
    const ChannelMapping& c = m.channels[i];
    if (c.desired_angle) {
      run.commanded.push_back(c.motor);
      plan.push_back(MappedSeries(*c.desired_angle, ChannelField(i, "desired_angle"), table, m, source,
                                  run.desired_angle[c.motor]));
      plan.back().max_magnitude = kMaxAngleDegrees;
      plan.back().limp_torque = static_cast<int>(plan.size());  // the torque, next
      plan.push_back(MappedSeries(*c.desired_torque, ChannelField(i, "desired_torque"), table, m, source,
                                  run.desired_torque[c.motor]));
    }
    if (c.joint_angle) {
      run.motors.push_back(c.motor);
      plan.push_back(MappedSeries(*c.joint_angle, ChannelField(i, "joint_angle"), table, m, source,
                                  run.joint_angle[c.motor]));
      plan.back().max_magnitude = kMaxAngleDegrees;
    }
  }
  if (m.firmware_kp) {
    plan.push_back(RunInputSeries(*m.firmware_kp, "firmware_kp", "the servo's firmware gain", table, m, source,
                                  run.firmware_kp, run.firmware_kp_column));
  }
  if (m.winding_temperature) {
    plan.push_back(RunInputSeries(*m.winding_temperature, "winding_temperature", "the servo's winding temperature",
                                  table, m, source, run.winding_temperature, run.winding_temperature_column));
  }
  if (m.supply_voltage) {
    plan.push_back(RunInputSeries(*m.supply_voltage, "supply_voltage", "the servo's supply voltage", table, m, source,
                                  run.supply_voltage, run.supply_voltage_column));
  }
  for (size_t i = 0; i < m.accelerometers.size(); ++i) {
    const AccelerometerMapping& a = m.accelerometers[i];
    run.accelerometers.push_back(a.channel);
    if (a.noise) run.acceleration_noise[a.channel] = *a.noise;
    plan.push_back(MappedSeries(a.value, "accelerometers[" + std::to_string(i) + "]", table, m, source,
                                run.acceleration[a.channel]));
    plan.back().max_magnitude = kMaxAcceleration;
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------------------
// Rows and the time base

double ValueOf(const SeriesSource& s, const std::vector<std::string>& fields, const std::string& source, int line) {
  if (s.field < 0) return s.constant;
  const std::string& cell = fields[static_cast<size_t>(s.field)];
  const std::optional<double> raw = text::ParseDouble(cell);
  if (!raw || !std::isfinite(*raw)) {
    throw InputError(source, line, "column " + text::Quote(s.column) + ": " + text::Quote(cell) + " is not a finite number");
  }
  const double value = *raw * s.scale + s.offset;
  if (!std::isfinite(value)) {
    throw InputError(source, line, "column " + text::Quote(s.column) + ": " + text::Quote(cell) + " scaled by " +
                                       text::FormatDouble(s.scale) + " is not a finite number");
  }
  if (std::abs(value) > s.max_magnitude) {
    const bool acceleration = s.max_magnitude == kMaxAcceleration;
    const std::string unit = acceleration ? " m/s²" : "°";
    throw InputError(source, line,
                     "column " + text::Quote(s.column) + ": " + text::Quote(cell) + " gives " + text::FormatDouble(value) +
                         unit + (acceleration ? ", not an accelerometer's reading" : ", not a physical joint angle") +
                         " (expected −" + text::FormatDouble(s.max_magnitude) + "…" +
                         text::FormatDouble(s.max_magnitude) + unit + ")");
  }
  return value;
}

// An empty goal cell of a mapped run: the servo was limp there, which only its torque column can say (0 = torque
// off). The goal then stays the last one given (0 before any), since a limp servo ignores it. Without a torque
// column saying 0 the row would be replayed holding a made-up goal: that is an error naming the line and column.
void FillLimpGoal(const SeriesSource& goal, const SeriesSource& torque, const std::string& source, int line) {
  std::vector<double>& goals = *goal.values;
  const double torque_value = torque.values->back();
  if (torque.field < 0 || !(torque_value <= 0.0)) {
    const std::string said = torque.field < 0 ? "the mapping gives its torque as a constant"
                                              : "column " + text::Quote(torque.column) + " says " + text::FormatDouble(torque_value) +
                                                    " (torque on)";
    throw InputError(source, line,
                     "column " + text::Quote(goal.column) + " is empty, but " + said +
                         ": an empty goal is a limp segment only where a torque-enable column says 0 — map "
                         "'desired_torque' to the log's torque-enable column");
  }
  goals.back() = goals.size() >= 2 ? goals[goals.size() - 2] : 0.0;
}

void ReadRows(const Table& table, const std::vector<SeriesSource>& plan, char delimiter, const std::string& source,
              MeasuredRun& run) {
  for (const SeriesSource& s : plan) s.values->reserve(table.rows.size());
  for (const Line& row : table.rows) {
    const std::vector<std::string> fields = SplitFields(row.text, delimiter, source, row.number);
    if (fields.size() != table.columns.size()) {
      throw InputError(source, row.number,
                       "expected " + std::to_string(table.columns.size()) + " fields, found " +
                           std::to_string(fields.size()));
    }
    for (const SeriesSource& s : plan) {
      const bool limp = s.limp_torque >= 0 && s.field >= 0 && text::Trim(fields[static_cast<size_t>(s.field)]).empty();
      s.values->push_back(limp ? std::nan("") : ValueOf(s, fields, source, row.number));
    }
    for (const SeriesSource& s : plan) {
      if (s.limp_torque >= 0 && std::isnan(s.values->back())) FillLimpGoal(s, plan[static_cast<size_t>(s.limp_torque)], source, row.number);
    }
    run.lines.push_back(row.number);
  }
}

// Time starts at 0 and grows by one uniform step per row; sets run.step.
void CheckTimeBase(const std::string& column, MeasuredRun& run) {
  const std::vector<double>& t = run.time;
  const std::string where = "column " + text::Quote(column) + ": ";
  if (std::abs(t[0]) > kTimeZeroTolerance) {
    throw InputError(run.source, run.lines[0], where + "expected the first time to be 0 s, found " + Seconds(t[0]));
  }
  const double first_step = t[1] - t[0];
  for (size_t i = 1; i < t.size(); ++i) {
    const double step = t[i] - t[i - 1];
    if (!(step > 0.0)) {
      throw InputError(run.source, run.lines[i],
                       where + "expected a time after " + Seconds(t[i - 1]) + " (line " +
                           std::to_string(run.lines[i - 1]) + "), found " + Seconds(t[i]));
    }
    if (std::abs(step - first_step) > kStepRelativeTolerance * first_step) {
      throw InputError(run.source, run.lines[i],
                       where + "expected a uniform step of " + StepSeconds(first_step) +
                           " (that of the first two rows), found " + StepSeconds(step) + " from " +
                           Seconds(t[i - 1]) + " to " + Seconds(t[i]));
    }
  }
  run.step = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
}

// A log that reads the state, then sends commands, stamps both with the read's time: its row k's commands act from
// t(k) to t(k+1), which are row k+1's in orcs's timing. Row 0's (the start, before any step) keep their own.
void ShiftInputsToOrcsTiming(MeasuredRun& run) {
  const auto shift = [](std::vector<double>& values) {
    if (values.size() > 1) std::copy_backward(values.begin(), values.end() - 1, values.end());
  };
  for (auto& [motor, values] : run.desired_angle) shift(values);
  for (auto& [motor, values] : run.desired_torque) shift(values);
  shift(run.supply_voltage);
}

// One run has one firmware gain, and a gain is positive: a gain that changes within the run (a log of two
// settings) or a non-positive one is an error naming the column and the line.
void CheckFirmwareGain(const MeasuredRun& run) {
  const std::vector<double>& gain = run.firmware_kp;
  for (size_t i = 0; i < gain.size(); ++i) {
    if (!(gain[i] > 0.0)) {
      throw InputError(run.source, run.lines[i], run.firmware_kp_column + ": expected a positive firmware gain, found " +
                                                     text::FormatDouble(gain[i]));
    }
    if (gain[i] != gain[0]) {
      throw InputError(run.source, run.lines[i],
                       run.firmware_kp_column + ": the firmware gain changes within the run, from " +
                           text::FormatDouble(gain[0]) + " (line " + std::to_string(run.lines[0]) + ") to " +
                           text::FormatDouble(gain[i]) + "; a run has one gain — split the log where it changes");
    }
  }
}

// A winding temperature is one a servo can run at: −50 … 200 °C (a log in kelvin or °F would be far off).
void CheckWindingTemperature(const MeasuredRun& run) {
  const std::vector<double>& temperature = run.winding_temperature;
  for (size_t i = 0; i < temperature.size(); ++i) {
    if (temperature[i] < -50.0 || temperature[i] > 200.0) {
      throw InputError(run.source, run.lines[i],
                       run.winding_temperature_column + ": expected a winding temperature of −50 … 200 °C, found " +
                           text::FormatDouble(temperature[i]));
    }
  }
}

// A supply voltage is one a servo can run on: above 0, at most kMaxSupplyVoltage.
void CheckSupplyVoltage(const MeasuredRun& run) {
  const std::vector<double>& voltage = run.supply_voltage;
  for (size_t i = 0; i < voltage.size(); ++i) {
    if (!(voltage[i] > 0.0 && voltage[i] <= kMaxSupplyVoltage)) {
      throw InputError(run.source, run.lines[i],
                       run.supply_voltage_column + ": expected a supply voltage above 0 and at most " +
                           text::FormatDouble(kMaxSupplyVoltage) + " V, found " + text::FormatDouble(voltage[i]));
    }
  }
}

// The canonical form of a path, for comparing two names of one file.
std::filesystem::path Canonical(const std::string& path) {
  std::error_code error;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, error);
  if (!error) return canonical;
  return std::filesystem::absolute(path, error).lexically_normal();
}

}  // namespace

std::optional<double> FirmwareGain(const MeasuredRun& run) {
  if (run.firmware_kp.empty()) return std::nullopt;
  return run.firmware_kp.front();
}

std::optional<double> WindingTemperature(const MeasuredRun& run) {
  if (run.winding_temperature.empty()) return std::nullopt;
  double sum = 0.0;
  for (double t : run.winding_temperature) sum += t;
  return sum / static_cast<double>(run.winding_temperature.size());
}

std::string AccelerometerColumn(const std::string& agent, const std::string& channel) {
  return std::string(kSimPrefix) + agent + "/" + channel;
}

std::string MotorColumn(const std::string& agent, const std::string& motor, const std::string& quantity) {
  return std::string(kSimPrefix) + agent + "/" + motor + "/" + quantity;
}

ColumnMapping ParseColumnMapping(const nlohmann::json& j, const std::string& source) {
  if (!j.is_object()) {
    throw InputError(source, 0, "expected a column mapping (a JSON object), found " + DescribeJson(j));
  }
  const JsonNode root(j, "", source);
  root.ExpectOnly({"agent", "time", "channels", "delimiter", "firmware_kp", "winding_temperature", "supply_voltage",
                   "command_timing", "accelerometers"});
  ColumnMapping mapping;
  mapping.source = source;
  mapping.agent = root.At("agent").String("an agent name");
  mapping.time = ParseColumnSource(root.At("time"));
  for (const JsonNode& channel : root.At("channels").Elements()) mapping.channels.push_back(ParseChannel(channel));
  if (root.Has("delimiter")) mapping.delimiter = ParseDelimiter(root.At("delimiter"));
  if (root.Has("firmware_kp")) mapping.firmware_kp = ParseColumnSource(root.At("firmware_kp"));
  if (root.Has("winding_temperature")) mapping.winding_temperature = ParseColumnSource(root.At("winding_temperature"));
  if (root.Has("supply_voltage")) mapping.supply_voltage = ParseColumnSource(root.At("supply_voltage"));
  if (root.Has("command_timing")) mapping.command_timing = ParseCommandTiming(root.At("command_timing"));
  if (root.Has("accelerometers")) {
    for (const JsonNode& axis : root.At("accelerometers").Elements()) {
      mapping.accelerometers.push_back(ParseAccelerometer(axis));
    }
  }
  CheckMapping(mapping);
  return mapping;
}

ColumnMapping ReadColumnMapping(const std::string& path) {
  return ParseColumnMapping(ParseJson(ReadTextFile(path), path), path);
}

MeasuredRun ParseMeasuredRun(std::string_view text, const std::string& source, const ColumnMapping* mapping) {
  if (IsBamLog(text)) {  // BAM's JSON log: read as the table of its CSV conversion (model/identify/bam_log.h)
    const std::string bam_table = BamLogAsTable(text, source);
    const ColumnMapping bam_mapping = mapping ? *mapping : BamLogMapping(bam_table, source);
    return ParseMeasuredRun(bam_table, source, &bam_mapping);
  }
  const Table table = ReadTable(text, source, mapping);
  MeasuredRun run;
  run.source = source;
  const std::vector<SeriesSource> plan =
      mapping ? MappedPlan(table, *mapping, source, run) : NativePlan(table, source, run);
  ReadRows(table, plan, mapping ? mapping->delimiter : kNativeDelimiter, source, run);
  CheckTimeBase(plan.front().column, run);
  if (mapping) run.command_timing = mapping->command_timing;
  if (run.command_timing == CommandTiming::kFromRow) ShiftInputsToOrcsTiming(run);
  CheckFirmwareGain(run);
  CheckWindingTemperature(run);
  CheckSupplyVoltage(run);
  return run;
}

MeasuredRun ReadMeasuredRun(const std::string& path, const ColumnMapping* mapping) {
  return ParseMeasuredRun(ReadTextFile(path, kMaxMeasuredRunBytes, "a measured run"), path, mapping);
}

void CheckRunsAgree(const std::vector<MeasuredRun>& runs, const std::string& role) {
  if (runs.empty()) return;
  const MeasuredRun& first = runs.front();
  for (const MeasuredRun& run : runs) {
    if (run.agent != first.agent) {
      throw InputError(run.source, 0,
                       role + " run of agent " + text::Quote(run.agent) + ", but " + first.source + " is of agent '" +
                           first.agent + "': all " + role + " runs must come from one rig");
    }
    if (std::abs(run.step - first.step) > kStepAgreeTolerance) {
      throw InputError(run.source, 0,
                       role + " run with a time step of " + StepSeconds(run.step) + ", but " + first.source + " has " +
                           StepSeconds(first.step) + ": all " + role + " runs must share one time step");
    }
  }
}

void CheckDisjoint(const std::vector<std::string>& fit_paths, const std::vector<std::string>& holdout_paths) {
  for (const std::string& holdout : holdout_paths) {
    for (const std::string& fit : fit_paths) {
      if (Canonical(holdout) == Canonical(fit)) {
        throw InputError(holdout, 0, "a holdout run is also a fit run: the same file as " + fit);
      }
    }
  }
  std::vector<std::string> fit_contents;
  fit_contents.reserve(fit_paths.size());
  for (const std::string& fit : fit_paths) fit_contents.push_back(ReadTextFile(fit, kMaxMeasuredRunBytes, "a measured run"));
  for (const std::string& holdout : holdout_paths) {
    const std::string contents = ReadTextFile(holdout, kMaxMeasuredRunBytes, "a measured run");
    for (size_t i = 0; i < fit_paths.size(); ++i) {
      if (contents == fit_contents[i]) {
        throw InputError(holdout, 0, "a holdout run is also a fit run: the same contents as " + fit_paths[i]);
      }
    }
  }
}

control::KeyframeRecord CommandsAsRecord(const MeasuredRun& run, const std::vector<std::string>& motor_order) {
  std::vector<std::pair<const std::vector<double>*, const std::vector<double>*>> inputs;
  const auto commanded = std::count_if(motor_order.begin(), motor_order.end(), [&](const std::string& motor) {
    return run.desired_angle.count(motor) != 0 && run.desired_torque.count(motor) != 0;
  });
  for (const std::string& motor : motor_order) {
    const auto angle = run.desired_angle.find(motor);
    const auto torque = run.desired_torque.find(motor);
    if (angle == run.desired_angle.end() || torque == run.desired_torque.end()) {
      const char* missing = angle == run.desired_angle.end() ? "DesiredAngle" : "DesiredTorque";
      // A replay drives every motor of the agent: say how to give the ones the log lacks.
      throw InputError(run.source, 0,
                       "no column '" + MotorColumn(run.agent, motor, missing) + "': a replay drives every motor of " +
                           run.agent + ", and the run commands " + std::to_string(commanded) + " of its " +
                           std::to_string(motor_order.size()) + " motors; log the others' commands, or give each in "
                           "the column mapping as constants, e.g. {\"motor\": \"" + motor +
                           "\", \"desired_angle\": {\"constant\": 0}, \"desired_torque\": {\"constant\": 1}} "
                           "(docs/gap_measured_data.md)");
    }
    inputs.emplace_back(&angle->second, &torque->second);
  }
  control::KeyframeRecord record;
  record.source = run.source;
  record.motor_count = static_cast<int>(motor_order.size());
  for (size_t i = 1; i < run.time.size(); ++i) {
    control::Keyframe frame;
    frame.time_ms = std::max(0.0, run.time[i - 1] - run.step / 2.0) * 1000.0;
    const size_t input_row = run.command_timing == CommandTiming::kFromRow ? i - 1 : i;  // the line it was read from
    frame.line = input_row < run.lines.size() ? run.lines[input_row] : 0;
    frame.inputs.reserve(2 * inputs.size());
    for (const auto& [angle, torque] : inputs) {
      frame.inputs.push_back(angle->at(i));
      frame.inputs.push_back(torque->at(i));
    }
    record.frames.push_back(std::move(frame));
  }
  return record;
}

}  // namespace orcs::identify
