#include "model/scene/scenario.h"

#include "base/demand.h"
#include "model/scene/environment_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::scene {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------------------
// Resolution: file references → inline content

// The file a scenario field names, relative to the scenario's folder.
std::string Referenced(const fs::path& folder, const JsonNode& node) {
  const std::string name = node.String("a file name");
  const fs::path path = fs::path(name).is_absolute() ? fs::path(name) : folder / name;
  return path.lexically_normal().string();
}

// Reads a referenced file; an unreadable one is named together with the field that references it.
std::string ReadReferenced(const fs::path& folder, const JsonNode& node) {
  const std::string path = Referenced(folder, node);
  try {
    return ReadTextFile(path);
  } catch (const InputError&) {
    node.Fail("a readable file", "'" + path + "', which cannot be read");
  }
}

Json AssignmentsJson(const std::vector<ValueAssignment>& assignments) {
  Json out = Json::array();
  for (const ValueAssignment& a : assignments) out.push_back({a.path, a.value, a.file, a.line});
  return out;
}

Json ResolveValueFile(const fs::path& folder, const JsonNode& node) {
  if (node.value().is_object()) return node.value();  // already resolved
  const std::string path = Referenced(folder, node);
  return {{"file", node.String("a file name")}, {"assignments", AssignmentsJson(ValueFile::Read(path))}};
}

Json ResolveValueFiles(const fs::path& folder, const JsonNode& list) {
  Json out = Json::array();
  for (const JsonNode& element : list.Elements()) out.push_back(ResolveValueFile(folder, element));
  return out;
}

// Every "record": "file" and "script": "file" member below `node` (controller and fitness sections) becomes
// {"file", "text"}: a keyframe record, a Lua script (docs/extending.md).
void ResolveRecords(const fs::path& folder, Json& value, const JsonNode& node) {
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it) {
      const JsonNode child = node.At(it.key());
      if ((it.key() == "record" || it.key() == "script") && it.value().is_string()) {
        it.value() = {{"file", it.value().get<std::string>()}, {"text", ReadReferenced(folder, child)}};
      } else {
        ResolveRecords(folder, it.value(), child);
      }
    }
  } else if (value.is_array()) {
    const std::vector<JsonNode> elements = node.Elements();
    for (std::size_t i = 0; i < value.size(); ++i) ResolveRecords(folder, value[i], elements[i]);
  }
}

// ---------------------------------------------------------------------------------------------------------
// Parsing

std::vector<ValueAssignment> AssignmentsOf(const JsonNode& node) {
  std::vector<ValueAssignment> assignments;
  for (const JsonNode& element : node.Elements()) {
    const std::vector<JsonNode> fields = element.Elements();
    if (fields.size() != 4) element.Fail("[path, value, file, line]");
    assignments.push_back({fields[0].String("a repository path"), fields[1].String("a value text"),
                           fields[2].String("a file name"), fields[3].Integer("a line number")});
  }
  return assignments;
}

}  // namespace

std::vector<ValueAssignment> ParseInlineValues(const JsonNode& node) {
  std::vector<ValueAssignment> assignments;
  for (const auto& [path, value] : node.Members()) {
    std::string text;
    if (value.value().is_boolean()) {
      text = value.value().get<bool>() ? "T" : "F";
    } else if (value.value().is_number()) {
      text = text::FormatDouble(value.Number("a number"));
    } else {
      text = value.String("a number, a boolean or a string");
    }
    assignments.push_back({path, text, node.source() + ": field " + text::Quote(value.path()), 0});
  }
  return assignments;
}

namespace {

// The name of a scenario that gives none: its file's stem, made a name that keeps the rule (a file's stem has no
// '/', but may have 250 bytes, a '\\', a control character, or be ".."; a job's source is "job <id> scenario").
std::string DefaultName(const std::string& source) {
  std::string name(text::Prefix(fs::path(source).stem().string(), text::kMaxNameBytes));
  for (char& c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\\' || byte < 0x20 || byte == 0x7f) c = '_';
  }
  return text::NameProblem(name).empty() ? name : "scenario";  // "", ".", "..", not UTF-8
}

// "name": a label, and the folder its results go to (runs/<name>), so never a path.
void ReadName(const JsonNode& root, Scenario& scenario) {
  if (!root.Has("name")) {
    scenario.name = DefaultName(scenario.source);
    return;
  }
  const JsonNode name = root.At("name");
  scenario.name = name.String(text::NameRule());
  const std::string problem = text::NameProblem(scenario.name);
  if (!problem.empty()) name.Fail(text::NameRule(), DescribeJson(name.value()) + " (" + problem + ")");
}

void ReadEnvironment(const JsonNode& root, Scenario& scenario) {
  scenario.environment_name = "(default: one A-Series named Humanoid)";
  if (!root.Has("environment")) return;
  const JsonNode environment = root.At("environment");
  if (environment.value().is_string()) {
    environment.Fail("an inlined environment {\"file\", \"xml\"} (resolve the scenario file first)");
  }
  environment.ExpectOnly({"file", "xml"});
  scenario.environment_xml = environment.At("xml").String("ORCS XML text");
  scenario.environment_name = environment.StringOr("file", "(inline)", "a file name");
}

ParameterDistribution ReadDistribution(const JsonNode& node) {
  node.ExpectOnly({"path", "match", "uniform", "normal", "relative"});
  ParameterDistribution distribution;
  if (node.Has("path") == node.Has("match")) node.Fail("exactly one of 'path' or 'match'", "both or none");
  if (node.Has("match")) {
    distribution.match = node.At("match").String("a regular expression of repository paths");
    if (distribution.match.empty()) node.At("match").Fail("a regular expression of repository paths");
  } else {
    distribution.path = node.At("path").String("a repository path");
    if (distribution.path.empty() || distribution.path[0] != '/') node.At("path").Fail("a path starting with '/'");
  }
  distribution.relative = node.Has("relative") && node.At("relative").Bool("true or false");
  if (node.Has("uniform") == node.Has("normal")) node.Fail("exactly one of 'uniform' or 'normal'", "both or none");
  if (node.Has("uniform")) {
    const JsonNode uniform = node.At("uniform");
    const std::vector<double> range = uniform.Numbers("[low, high]");
    if (range.size() != 2) uniform.Fail("[low, high]");
    if (range[0] > range[1]) uniform.Fail("low ≤ high", "[" + text::FormatDouble(range[0]) + ", " +
                                                             text::FormatDouble(range[1]) + "]");
    distribution.kind = ParameterDistribution::Kind::kUniform;
    distribution.low = range[0];
    distribution.high = range[1];
  } else {
    const JsonNode normal = node.At("normal");
    normal.ExpectOnly({"mean", "deviation", "min", "max"});
    distribution.kind = ParameterDistribution::Kind::kNormal;
    distribution.mean = normal.At("mean").Number("a number");
    distribution.deviation = normal.At("deviation").Number("a number ≥ 0");
    if (distribution.deviation < 0) normal.At("deviation").Fail("a number ≥ 0");
    distribution.low = normal.NumberOr("min", -kInfinity, "a number");
    distribution.high = normal.NumberOr("max", kInfinity, "a number");
    if (distribution.low > distribution.high) {
      normal.At("min").Fail("min ≤ max (" + text::FormatDouble(distribution.high) + ")");
    }
  }
  return distribution;
}

// The shipped default randomisation of the motor model and the floor friction (docs/scenarios.md).
void AddDefaultMotorRandomisation(std::vector<ParameterDistribution>& parameters) {
  const auto relative = [&](const char* path, double low, double high) {
    parameters.push_back({path, ParameterDistribution::Kind::kUniform, low, high, 0.0, 0.0, true, ""});
  };
  relative("/AngularMotor/PID/Proportional", 0.8, 1.2);
  relative("/AngularMotor/FMaxFactor", 0.9, 1.1);
  relative("/AngularMotor/MaxVelocity", 0.9, 1.1);
  relative("/AngularMotor/StaticFriction", 0.5, 1.5);
  relative("/AngularMotor/DynamicFriction", 0.7, 1.3);
  parameters.push_back({"/AngularMotor/DynamicFrictionOffset", ParameterDistribution::Kind::kUniform, 0.0, 0.01,
                        0.0, 0.0, false, ""});
  relative("/Simulation/ODE/FrictionScaling", 0.8, 1.2);
}

Randomisation ReadRandomisation(const JsonNode& node) {
  node.ExpectOnly({"sets", "default_motor_model", "parameters", "parameter_files", "start_pose"});
  Randomisation randomisation;
  const std::string sets_expected = "an integer from 1 to " + std::to_string(kMaxParameterSets);
  if (node.Has("sets")) {
    // Integer() refuses what does not fit an int (1e10) with the same words; 1e9 fits and is refused here, before
    // anything is allocated per set.
    randomisation.sets = node.At("sets").Integer(sets_expected);
    if (randomisation.sets < 1 || randomisation.sets > kMaxParameterSets) node.At("sets").Fail(sets_expected);
  }
  if (node.Has("default_motor_model") && node.At("default_motor_model").Bool("true or false")) {
    AddDefaultMotorRandomisation(randomisation.parameters);
  }
  if (node.Has("parameters")) {
    const JsonNode parameters = node.At("parameters");
    if (parameters.value().is_array() &&
        randomisation.parameters.size() + parameters.value().size() > kMaxRandomisedParameters) {
      parameters.Fail("at most " + std::to_string(kMaxRandomisedParameters) + " parameters" +
                      (randomisation.parameters.empty() ? "" : " with default_motor_model's " +
                                                                   std::to_string(randomisation.parameters.size())));
    }
    for (const JsonNode& element : parameters.Elements()) {
      randomisation.parameters.push_back(ReadDistribution(element));
    }
  }
  const std::size_t drawn = static_cast<std::size_t>(randomisation.sets) * randomisation.parameters.size();
  if (drawn > kMaxDrawnValues) {
    node.At("sets").Fail("at most " + std::to_string(kMaxDrawnValues) + " drawn values per job (sets × parameters)",
                         std::to_string(randomisation.sets) + " sets × " +
                             std::to_string(randomisation.parameters.size()) + " parameters");
  }
  if (node.Has("parameter_files")) {
    const JsonNode files = node.At("parameter_files");
    files.ExpectOnly({"files", "choice"});
    const std::string choice = files.StringOr("choice", "random", "\"random\" or \"sequence\"");
    if (choice != "random" && choice != "sequence") files.At("choice").Fail("\"random\" or \"sequence\"");
    randomisation.files_in_sequence = choice == "sequence";
    for (const JsonNode& file : files.At("files").Elements()) {
      if (!file.value().is_object()) file.Fail("an inlined value file (resolve the scenario file first)");
      file.ExpectOnly({"file", "assignments"});
      randomisation.parameter_files.push_back({file.At("file").String("a file name"),
                                               AssignmentsOf(file.At("assignments"))});
    }
  }
  if (node.Has("start_pose")) {
    const JsonNode pose = node.At("start_pose");
    pose.ExpectOnly({"position", "yaw_degrees", "motor_angle_degrees"});
    StartPoseRandomisation& start = randomisation.start_pose;
    if (pose.Has("position")) start.position = pose.At("position").Vector3("± m per axis");
    start.yaw_degrees = pose.NumberOr("yaw_degrees", 0.0, "± degrees");
    start.motor_angle_degrees = pose.NumberOr("motor_angle_degrees", 0.0, "± degrees");
    if (start.position.minCoeff() < 0) pose.At("position").Fail("three non-negative offsets (m)");
    if (start.yaw_degrees < 0 || start.yaw_degrees > 180) pose.At("yaw_degrees").Fail("0…180 degrees");
    if (start.motor_angle_degrees < 0 || start.motor_angle_degrees > 150) {
      pose.At("motor_angle_degrees").Fail("0…150 degrees");
    }
  }
  return randomisation;
}

void ReadFitnessAggregate(const JsonNode& fitness, Scenario& scenario) {
  if (!fitness.Has("aggregate")) return;
  const JsonNode aggregate = fitness.At("aggregate");
  const std::string name = aggregate.String("\"mean\", \"min\", \"max\" or \"quantile\"");
  if (name == "mean") {
    scenario.aggregate = Aggregate::kMean;
  } else if (name == "min") {
    scenario.aggregate = Aggregate::kMin;
  } else if (name == "max") {
    scenario.aggregate = Aggregate::kMax;
  } else if (name == "quantile") {
    scenario.aggregate = Aggregate::kQuantile;
    scenario.quantile = fitness.At("quantile").Number("a number 0…1");
    if (scenario.quantile < 0 || scenario.quantile > 1) fitness.At("quantile").Fail("a number 0…1");
  } else {
    aggregate.Fail("\"mean\", \"min\", \"max\" or \"quantile\"");
  }
}

// "fault": {"kind": "segfault" | "abort" | "hang" | "spin", "at_step": N}.
FaultInjection ReadFault(const JsonNode& node) {
  node.ExpectOnly({"kind", "at_step"});
  FaultInjection fault;
  const JsonNode kind = node.At("kind");
  const std::string name = kind.String("\"segfault\", \"abort\", \"hang\" or \"spin\"");
  if (name == "segfault") {
    fault.kind = FaultInjection::Kind::kSegfault;
  } else if (name == "abort") {
    fault.kind = FaultInjection::Kind::kAbort;
  } else if (name == "hang") {
    fault.kind = FaultInjection::Kind::kHang;
  } else if (name == "spin") {
    fault.kind = FaultInjection::Kind::kSpin;
  } else {
    kind.Fail("\"segfault\", \"abort\", \"hang\" or \"spin\"");
  }
  if (node.Has("at_step")) fault.at_step = node.At("at_step").Unsigned("a step index ≥ 0");
  return fault;
}

std::vector<ValueSchedule> ReadSchedules(const JsonNode& node) {
  if (!node.value().is_object()) node.Fail("an object of value paths and {\"times\": [...], \"values\": [...]}");
  std::vector<ValueSchedule> schedules;
  for (const auto& [path, entry] : node.Members()) {
    entry.ExpectOnly({"times", "values"});
    ValueSchedule& schedule = schedules.emplace_back();
    schedule.path = path;
    for (const JsonNode& time : entry.At("times").Elements()) {
      const double seconds = time.Number("seconds since the reset, at least 0, not decreasing");
      if (seconds < 0.0 || (!schedule.times.empty() && seconds < schedule.times.back())) {
        time.Fail("seconds since the reset, at least 0, not decreasing");
      }
      schedule.times.push_back(seconds);
    }
    for (const JsonNode& value : entry.At("values").Elements()) {
      schedule.values.push_back(value.Number("a finite number"));
    }
    if (schedule.values.size() != schedule.times.size()) {
      entry.At("values").Fail("one value per time (" + std::to_string(schedule.times.size()) + ")",
                              std::to_string(schedule.values.size()));
    }
  }
  return schedules;
}

}  // namespace

Scenario ParseScenario(const Json& resolved, const std::string& source) {
  const JsonNode root(resolved, "", source);
  root.ExpectOnly({"name", "environment", "value_files", "values", "duration", "agent", "controller", "fitness",
                   "randomisation", "start_angles", "schedules", "log", "genome", "fault", "evolution", "record",
                   "motor_model"});
  Scenario scenario;
  scenario.source = source;
  ReadName(root, scenario);
  ReadEnvironment(root, scenario);
  if (root.Has("value_files")) {
    for (const JsonNode& file : root.At("value_files").Elements()) {
      if (!file.value().is_object()) file.Fail("an inlined value file (resolve the scenario file first)");
      file.ExpectOnly({"file", "assignments"});
      const std::vector<ValueAssignment> assignments = AssignmentsOf(file.At("assignments"));
      scenario.values.insert(scenario.values.end(), assignments.begin(), assignments.end());
    }
  }
  if (root.Has("values")) {
    const std::vector<ValueAssignment> inline_values = ParseInlineValues(root.At("values"));
    scenario.values.insert(scenario.values.end(), inline_values.begin(), inline_values.end());
  }
  scenario.duration = root.NumberOr("duration", scenario.duration, "seconds > 0");
  if (!(scenario.duration > 0) || scenario.duration > 1e6) root.At("duration").Fail("seconds, 0 < duration ≤ 1e6");
  scenario.agent = root.StringOr("agent", scenario.agent, "an agent name");
  scenario.controller = root.At("controller").value();
  const JsonNode fitness = root.At("fitness");
  scenario.fitness = fitness.value();
  ReadFitnessAggregate(fitness, scenario);
  if (root.Has("motor_model")) {  // its form; whether a worker has the plug-in, only the worker knows
    const JsonNode model = root.At("motor_model");
    model.ExpectOnly({"plugin", "params"});
    const std::string name = model.At("plugin").String("\"<plug-in>/<component>\", e.g. \"example/pd\"");
    if (name.find('/') == std::string::npos || name.front() == '/' || name.back() == '/') {
      model.At("plugin").Fail("\"<plug-in>/<component>\", e.g. \"example/pd\"");
    }
    if (model.Has("params") && !model.At("params").value().is_object()) {
      model.At("params").Fail("an object of the plug-in's parameters");
    }
    scenario.motor_model = model.value();
  }
  if (root.Has("randomisation")) scenario.randomisation = ReadRandomisation(root.At("randomisation"));
  if (root.Has("start_angles")) {
    const JsonNode angles = root.At("start_angles");
    if (!angles.value().is_object()) angles.Fail("an object of motor names and degrees");
    for (const auto& [motor, value] : angles.value().items()) {
      const double degrees = angles.At(motor).Number("degrees, −150…150");
      if (!(std::abs(degrees) <= 150.0)) angles.At(motor).Fail("degrees, −150…150");
      scenario.start_angles.emplace_back(motor, degrees);
    }
  }
  if (root.Has("schedules")) scenario.schedules = ReadSchedules(root.At("schedules"));
  if (root.Has("log")) {
    const JsonNode log = root.At("log");
    if (log.value().is_array() && log.value().size() > kMaxLogPatterns) {
      log.Fail("at most " + std::to_string(kMaxLogPatterns) + " regular expressions");
    }
    for (const JsonNode& pattern : log.Elements()) {
      scenario.log.push_back(pattern.String("a regular expression"));
    }
  }
  if (root.Has("genome")) {
    const JsonNode genome = root.At("genome");
    if (!genome.value().is_array() && !genome.value().is_object()) genome.Fail("an array of numbers or a network object");
    scenario.genome = genome.value();
  }
  if (root.Has("fault")) scenario.fault = ReadFault(root.At("fault"));
  if (root.Has("evolution")) {
    const JsonNode evolution = root.At("evolution");
    if (!evolution.value().is_object()) evolution.Fail("an object (orcs-batch evolve's settings)");
    scenario.evolution = evolution.value();
  }
  if (root.Has("record")) scenario.record = root.At("record").Bool("true or false");
  return scenario;
}

void SetScenarioEngine(Json& resolved, const std::string& engine) {
  if (!resolved.contains("values") || resolved["values"].is_null()) resolved["values"] = Json::object();
  if (resolved["values"].is_object()) resolved["values"]["/Simulation/Engine"] = engine;  // else ParseScenario says why
}

Json ResolveScenarioFile(const std::string& path) {
  Json scenario = ParseJson(ReadTextFile(path), path);
  const JsonNode root(scenario, "", path);
  if (!scenario.is_object()) root.Fail("a JSON object");
  const fs::path folder = fs::path(path).parent_path();
  if (root.Has("environment") && scenario["environment"].is_string()) {
    const JsonNode environment = root.At("environment");
    // The robot files it names travel inline, as the environment does (docs/formats.md, "Robot files").
    scenario["environment"] = {{"file", environment.String("a file name")},
                               {"xml", EnvironmentReader::InlineRobotFiles(ReadReferenced(folder, environment),
                                                                           Referenced(folder, environment))}};
  }
  if (root.Has("value_files")) scenario["value_files"] = ResolveValueFiles(folder, root.At("value_files"));
  if (root.Has("randomisation") && scenario["randomisation"].is_object() &&
      scenario["randomisation"].contains("parameter_files") &&
      scenario["randomisation"]["parameter_files"].is_object() &&
      scenario["randomisation"]["parameter_files"].contains("files")) {
    const JsonNode files = root.At("randomisation").At("parameter_files").At("files");
    scenario["randomisation"]["parameter_files"]["files"] = ResolveValueFiles(folder, files);
  }
  for (const char* section : {"controller", "fitness"}) {
    if (!root.Has(section)) continue;
    Json copy = scenario[section];
    ResolveRecords(folder, copy, root.At(section));
    scenario[section] = std::move(copy);
  }
  return scenario;
}

double AggregateFitness(std::vector<double> values, Aggregate aggregate, double quantile) {
  ORCS_DEMAND_MSG(!values.empty(), "AggregateFitness needs one value per parameter set");
  switch (aggregate) {
    case Aggregate::kMean: {
      double sum = 0.0;
      for (double value : values) sum += value;
      return sum / static_cast<double>(values.size());
    }
    case Aggregate::kMin:
      return *std::min_element(values.begin(), values.end());
    case Aggregate::kMax:
      return *std::max_element(values.begin(), values.end());
    case Aggregate::kQuantile: {
      std::sort(values.begin(), values.end());
      const double position = quantile * static_cast<double>(values.size() - 1);
      const auto below = static_cast<std::size_t>(std::floor(position));
      const std::size_t above = std::min(below + 1, values.size() - 1);
      return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
    }
  }
  return 0.0;
}

double DefaultTimeLimitSeconds(double simulated_seconds) {
  constexpr double kMarginSeconds = 30.0;
  constexpr double kWallSecondsPerSimulatedSecond = 10.0;
  return kMarginSeconds + kWallSecondsPerSimulatedSecond * std::max(0.0, simulated_seconds);
}

double DefaultTimeLimitSeconds(const Scenario& scenario) {
  return DefaultTimeLimitSeconds(scenario.duration * static_cast<double>(std::max(1, scenario.randomisation.sets)));
}

}  // namespace orcs::scene
