#include "model/identify/replay.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "base/near_names.h"
#include "model/control/keyframe_record.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/text_file.h"
#include "model/evaluation/recorder.h"
#include "model/scene/environment_reader.h"
#include "model/scene/scenario.h"
#include "model/scene/simulation.h"

namespace orcs::identify {
namespace {

std::string PendulumXml(const RigOptions& options, const std::string& agent) {
  for (double value : {options.pole_mass, options.pole_length}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw InputError("--pole-mass and --pole-length must be positive and finite, found " +
                       text::FormatDouble(value));
    }
  }
  return "<?xml version=\"1.0\"?>\n<ORCS version=\"1.0\">\n  <Agent>\n    <Pendulum name=\"" + agent +
         "\" position=\"(0,0.5,0)\" poleMass=\"" + text::FormatDouble(options.pole_mass) + "\" poleLength=\"" +
         text::FormatDouble(options.pole_length) + "\"/>\n  </Agent>\n</ORCS>\n";
}

scene::EnvironmentDescription EnvironmentOf(const Rig& rig) {
  return scene::EnvironmentReader::ReadStringOrDefault(rig.environment_xml, rig.environment_name);
}

nlohmann::json ValuesObject(const std::vector<ValueAssignment>& model) {
  nlohmann::json values = nlohmann::json::object();
  for (const ValueAssignment& assignment : model) values[assignment.path] = assignment.value;
  values["/AngularMotor/IncludeNoise"] = false;  // the replay is the model's expectation; noise is the data's
  values["/AccelSensor/Deviation"] = 0;            // the accelerometers' too
  return values;
}

std::string ColumnPath(const MeasuredRun& run, const std::string& motor, const char* value) {
  return "/Sim/" + run.agent + "/" + motor + "/" + value;
}

void CheckRunFitsRig(const Rig& rig, const MeasuredRun& run) {
  if (run.agent != rig.agent) {
    throw InputError(run.source + ": the columns are of agent " + text::Quote(run.agent) + ", the rig's agent is '" + rig.agent +
                     "'");
  }
  if (std::abs(run.step - rig.step) > 1e-9) {
    // What to change: the log's rows, or the rig's step (a whole number of simulation steps per row).
    const double ratio = run.step / rig.step;
    const std::string fix =
        std::abs(ratio - std::round(ratio)) < 1e-6 && ratio > 1.5
            ? "; log a row every " + text::FormatDouble(rig.step) + " s, or make the rig's row the log's: a --model value "
              "file with /Simulation/IterationsPerStep=" + text::FormatDouble(std::round(ratio)) + " (" +
              text::FormatDouble(std::round(ratio)) + " steps of " + text::FormatDouble(rig.step) +
              " s a row, IterationsPerStep being 1 now; docs/gap_measured_data.md)"
            : "; log a row every " + text::FormatDouble(rig.step) + " s (resample the log), or give the rig the log's step: "
              "a --model value file with /Simulation/TimeStepSize=" + text::FormatDouble(run.step) +
              " and /Simulation/IterationsPerStep=1 (docs/gap_measured_data.md)";
    throw InputError(run.source + ": column 'time': steps of " + text::FormatDouble(run.step) +
                     " s, but the rig simulates steps of " + text::FormatDouble(rig.step) +
                     " s (/Simulation/TimeStepSize × /Simulation/IterationsPerStep)" + fix);
  }
  for (const std::string& motor : run.motors) {
    bool known = false;
    for (const std::string& rig_motor : rig.motors) known = known || rig_motor == motor;
    if (!known) {
      throw InputError(run.source + ": column '" + ColumnPath(run, motor, "JointAngle") + "': agent '" + rig.agent +
                       "' of " + rig.environment_name + " has no motor " + text::Quote(motor) +
                       DidYouMean(motor, rig.motors));
    }
  }
}

// The run's firmware gain and winding temperature as values of its replay, after the model's: they are the run's
// inputs, not the model's. Without a gain the servo model cannot replay the run; without a temperature the
// winding is at the model's.
void AddRunInputs(const Rig& rig, const MeasuredRun& run, const std::vector<ValueAssignment>& model,
                  nlohmann::json& values) {
  if (const std::optional<double> temperature = WindingTemperature(run)) {
    values["/Servo/WindingTemperature"] = text::FormatDouble(*temperature);
  }
  const std::optional<double> gain = FirmwareGain(run);
  if (gain) {
    values["/Servo/FirmwareKp"] = text::FormatDouble(*gain);
  } else if (UsesServo(rig, model)) {
    throw InputError(run.source + ": no firmware gain: the servo model (/Servo/Enabled) needs the P gain the servo "
                     "ran with; map 'firmware_kp' to its column, header key or a constant, or log the column "
                     "'/Servo/FirmwareKp' (docs/gap_measured_data.md)");
  }
}

// A run input given per row as a scenario schedule, timed as the row's commands are (CommandsAsRecord): row i's
// value holds during the step that ends at row i, from half a step before that step starts.
nlohmann::json RowSchedule(const MeasuredRun& run, const std::vector<double>& values) {
  std::vector<double> times;
  std::vector<double> held;
  for (std::size_t i = 1; i < run.time.size(); ++i) {
    times.push_back(std::max(0.0, run.time[i - 1] - run.step / 2.0));
    held.push_back(values[i]);
  }
  return {{"times", times}, {"values", held}};
}

// Each accelerometer axis's weight in the loss: the angle sensor's noise (/AngularMotor/SensorNoiseDeviation, degrees)
// over the axis's (the mapping's "noise", else its board's /Sim/<agent>/<board>/AccelSensor/Deviation, m/s²), so
// that a residual of one σ weighs the same in either.
std::vector<double> AccelerationWeights(const Rig& rig, const MeasuredRun& run,
                                        const std::vector<ValueAssignment>& model) {
  std::vector<std::string> paths = {"/AngularMotor/SensorNoiseDeviation"};
  for (const std::string& channel : run.accelerometers) {
    paths.push_back("/Sim/" + run.agent + "/" + channel.substr(0, channel.find('/')) + "/AccelSensor/Deviation");
  }
  std::vector<double> values;
  try {
    values = ModelValues(rig, model, paths);
  } catch (const InputError&) {
    throw InputError(run.source + ": an accelerometer column names a board that agent '" + run.agent + "' of " +
                     rig.environment_name + " does not have (its boards: ABFR, ABHR, ABSR, ABAR, ABFL, ABHL, ABML, "
                     "ABAL on the A-Series)");
  }
  std::vector<double> weights;
  for (std::size_t i = 0; i < run.accelerometers.size(); ++i) {
    const auto given = run.acceleration_noise.find(run.accelerometers[i]);
    const double noise = given != run.acceleration_noise.end() ? given->second : values[i + 1];
    if (!(noise > 0.0) || !(values[0] > 0.0)) {
      throw InputError(run.source + ": column '" + AccelerometerColumn(run.agent, run.accelerometers[i]) +
                       "': the accelerometer's noise is " + text::FormatDouble(noise) + " m/s² and the angle sensor's " +
                       text::FormatDouble(values[0]) + "°; both must be positive to weigh the two (set "
                       "/AccelSensor/Deviation in --model, or \"noise\" in the mapping)");
    }
    weights.push_back(values[0] / noise);
  }
  return weights;
}

}  // namespace

Rig MakeRig(const RigOptions& options, const std::string& agent, const std::vector<ValueAssignment>& model) {
  Rig rig;
  rig.kind = options.kind;
  rig.agent = agent;
  rig.start_measured = options.start_measured;
  if (options.kind == "pendulum") {
    rig.environment_name = "(pendulum rig)";
    rig.environment_xml = PendulumXml(options, agent);
  } else if (options.kind == "aseries") {
    rig.environment_name = options.environment_file.empty() ? "(default A-Series)" : options.environment_file;
    if (!options.environment_file.empty()) rig.environment_xml = ReadTextFile(options.environment_file);
  } else {
    throw InputError("--rig: expected 'aseries' or 'pendulum', found " + text::Quote(options.kind));
  }
  scene::Simulation simulation;
  simulation.LoadEnvironment(EnvironmentOf(rig));
  simulation.Build();
  ValueFile::ApplyAssignments(model, simulation.repository());
  const int index = simulation.FindAgent(agent);
  if (index < 0) {
    // The pendulum rig's agent is "Pendulum": its runs on the default rig are the commonest slip.
    const std::string hint = options.kind != "pendulum" && agent == "Pendulum"
                                 ? "; the runs are a pendulum rig's: add --rig pendulum"
                                 : "; give the runs' environment with --env, or --rig pendulum for a pendulum";
    throw InputError(rig.environment_name + ": no agent " + text::Quote(agent) + " (the runs' agent)" + hint);
  }
  for (const auto& motor : simulation.model().morphology(index).motors) {
    rig.motors.push_back(motor.name);
    rig.motor_ranges.push_back({motor.min_degrees, motor.max_degrees});
  }
  for (const auto& body : simulation.model().morphology(index).bodies) rig.links.push_back(body.name);
  simulation.Reset();  // the model's values may choose another engine, which takes effect at a reset
  rig.step = simulation.StepDuration();
  return rig;
}

namespace {

// The rig's repository under `model`, each of `paths` read by `read` (a value → T).
template <typename T, typename Read>
std::vector<T> ReadModel(const Rig& rig, const std::vector<ValueAssignment>& model,
                         const std::vector<std::string>& paths, Read read) {
  scene::Simulation simulation;
  simulation.LoadEnvironment(EnvironmentOf(rig));
  simulation.Build();
  ValueFile::ApplyAssignments(model, simulation.repository());
  std::vector<T> values;
  for (const std::string& path : paths) values.push_back(read(simulation.repository().Get(path)));
  return values;
}

}  // namespace

std::vector<double> ModelValues(const Rig& rig, const std::vector<ValueAssignment>& model,
                                const std::vector<std::string>& paths) {
  return ReadModel<double>(rig, model, paths, [](const auto& value) { return value.as_double(); });
}

std::vector<bool> ModelSwitches(const Rig& rig, const std::vector<ValueAssignment>& model,
                                const std::vector<std::string>& paths) {
  return ReadModel<bool>(rig, model, paths, [](const auto& value) { return value.as_bool(); });
}

bool UsesServo(const Rig& rig, const std::vector<ValueAssignment>& model) {
  return ModelSwitches(rig, model, {"/Servo/Enabled"})[0];
}

ReplayRun MakeReplayRun(const Rig& rig, const MeasuredRun& run, const std::vector<ValueAssignment>& model) {
  CheckRunFitsRig(rig, run);
  ReplayRun replay;
  replay.source = run.source;
  replay.name = std::filesystem::path(run.source).stem().string();
  replay.run = &run;
  replay.channels = run.motors;
  const control::KeyframeRecord record = CommandsAsRecord(run, rig.motors);
  nlohmann::json angles = nlohmann::json::object();
  for (const std::string& motor : replay.channels) {
    const std::vector<double>& measured = run.joint_angle.at(motor);
    angles[motor] = std::vector<double>(measured.begin() + 1, measured.end());  // row k+1 follows step k+1
    replay.samples += measured.size() - 1;
  }
  nlohmann::json term = {{"type", "measured_error"}, {"angles", angles}};
  if (!run.accelerometers.empty()) {
    replay.accelerometers = run.accelerometers;
    replay.acceleration_weights = AccelerationWeights(rig, run, model);
    nlohmann::json accelerations = nlohmann::json::object();
    for (std::size_t i = 0; i < run.accelerometers.size(); ++i) {
      const std::vector<double>& measured = run.acceleration.at(run.accelerometers[i]);
      accelerations[run.accelerometers[i]] = {{"values", std::vector<double>(measured.begin() + 1, measured.end())},
                                              {"weight", replay.acceleration_weights[i]}};
      replay.samples += measured.size() - 1;
    }
    term["accelerations"] = accelerations;
  }
  nlohmann::json scenario = {
      {"name", "gap:" + replay.name},
      {"agent", rig.agent},
      {"duration", run.time.back()},
      {"controller", {{"type", "keyframes"}, {"record", {{"file", run.source}, {"text", control::FormatKeyframeRecord(record, {})}}}}},
      {"fitness", {{"terms", nlohmann::json::array({term})}}},
      {"values", ValuesObject(model)},
  };
  AddRunInputs(rig, run, model, scenario["values"]);
  for (const std::string& channel : run.accelerometers) {  // a board's own noise, should the model set one
    scenario["values"]["/Sim/" + run.agent + "/" + channel.substr(0, channel.find('/')) + "/AccelSensor/Deviation"] = 0;
  }
  if (!run.supply_voltage.empty()) scenario["schedules"]["/Servo/SupplyVoltage"] = RowSchedule(run, run.supply_voltage);
  if (rig.start_measured) {
    for (const std::string& motor : replay.channels) scenario["start_angles"][motor] = run.joint_angle.at(motor).front();
  }
  if (!rig.environment_xml.empty()) {
    scenario["environment"] = {{"file", rig.environment_name}, {"xml", rig.environment_xml}};
  }
  replay.scenario = std::move(scenario);
  return replay;
}

std::string MeasuredRecording(const Rig& rig, const std::vector<ValueAssignment>& model, const ReplayRun& replay) {
  const MeasuredRun& run = *replay.run;
  scene::Simulation simulation;
  simulation.LoadEnvironment(EnvironmentOf(rig));
  simulation.Build();
  std::vector<ValueAssignment> values = model;
  values.push_back({"/AngularMotor/IncludeNoise", "F", "orcs-gap", 0});  // JointAngle reads the pose as set
  ValueFile::ApplyAssignments(values, simulation.repository());
  const int agent = simulation.FindAgent(rig.agent);
  if (agent < 0) throw InputError(rig.environment_name + ": no agent " + text::Quote(rig.agent) + " (the runs' agent)");
  const std::vector<aseries::MorphologyMotor>& motors = simulation.model().morphology(agent).motors;
  // The measured column of each of the agent's motors (null: not measured).
  std::vector<const std::vector<double>*> columns(motors.size(), nullptr);
  for (std::size_t m = 0; m < motors.size(); ++m) {
    const auto found = run.joint_angle.find(motors[m].name);
    if (found != run.joint_angle.end()) columns[m] = &found->second;
  }
  std::vector<double> angles(motors.size(), 0.0);
  const auto pose = [&](std::size_t row) {
    simulation.Reset();
    for (std::size_t m = 0; m < motors.size(); ++m) {
      const double measured = columns[m] != nullptr ? (*columns[m])[row] : 0.0;
      angles[m] = std::clamp(std::isfinite(measured) ? measured : 0.0, motors[m].min_degrees, motors[m].max_degrees);
    }
    simulation.SetAgentJointAngles(agent, angles);
  };
  pose(0);
  evaluation::Recorder recorder(simulation, {"orcs-gap", rig.environment_name, "gap:" + replay.name + " (measured)",
                                             0, 0, nlohmann::json()});  // frame 0: row 0, at time 0
  for (std::size_t row = 1; row < run.time.size(); ++row) {
    pose(row);
    recorder.SampleAt(run.time[row]);
  }
  return recorder.Finish();
}

}  // namespace orcs::identify
