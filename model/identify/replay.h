// Replaying measured runs in simulation (docs/gap.md): the rig a run was recorded on, and one job per run and
// model that plays the run's commands into the rig and scores the simulated joint angles against the measured
// ones (fitness term "measured_error", degrees RMS). The replays are ordinary scenarios, so any worker of any
// broker runs them (clients/gap/broker_replays.h makes them jobs).
#pragma once

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "model/identify/measured_run.h"
#include "model/core/value_file.h"

namespace orcs::identify {

/// A value assignment for a job: repository path and value text.
using Override = std::pair<std::string, std::string>;

/// What the runs were recorded on.
struct RigOptions {
  std::string kind = "aseries";  ///< "aseries" (any environment with A-Series agents) or "pendulum"
  std::string environment_file;  ///< aseries: an ORCS XML environment; "" = one A-Series standing on the floor
  double pole_mass = 0.5;        ///< pendulum: kg
  double pole_length = 0.3;      ///< pendulum: m
  /// Each replay starts with the measured motors at the run's first measured angles (scenario "start_angles"), as
  /// a real robot starts where it was; false: at the built pose, as an orcs-sim log does (its row 0 is that pose).
  bool start_measured = false;
};

/// The rig, ready to put into a scenario.
struct Rig {
  std::string kind;              ///< "aseries" or "pendulum"
  std::string environment_name;  ///< the file, "(pendulum rig)" or "(default A-Series)", for messages
  std::string environment_xml;   ///< the ORCS XML; "" = the default A-Series world
  std::string agent;             ///< the agent the runs belong to
  std::vector<std::string> motors;  ///< its motors in input order
  std::vector<std::array<double, 2>> motor_ranges;  ///< per motor: its hinge stops [min, max], degrees
  std::vector<std::string> links;  ///< its bodies ("Right/LowerArm"): /Sim/<agent>/<link>/Mass is each one's mass
  /// s per simulation step under the model, one logged row: /Simulation/TimeStepSize × IterationsPerStep (the
  /// firmware and the physics run every iteration, with the row's goal held)
  double step = 0.01;
  bool start_measured = false;   ///< RigOptions::start_measured
};

/// Builds the rig for agent `agent` under the model's values and checks it has that agent. Throws InputError for
/// an unknown kind, an unreadable environment, a pole that is not positive and finite, or a missing agent.
Rig MakeRig(const RigOptions& options, const std::string& agent, const std::vector<ValueAssignment>& model);

/// The values of `paths` in the rig's world under the model (numbers). Throws InputError for an unknown path.
std::vector<double> ModelValues(const Rig& rig, const std::vector<ValueAssignment>& model,
                                const std::vector<std::string>& paths);

/// The values of the switches `paths` (booleans) in the rig's world under the model. Throws InputError for an
/// unknown path.
std::vector<bool> ModelSwitches(const Rig& rig, const std::vector<ValueAssignment>& model,
                                const std::vector<std::string>& paths);

/// Whether the model runs the physical servo (/Servo/Enabled = true in the rig under `model`).
bool UsesServo(const Rig& rig, const std::vector<ValueAssignment>& model);

/// One measured run as a replay job template.
struct ReplayRun {
  std::string name;                   ///< the file's stem, unique among the runs
  std::string source;                 ///< the file
  const MeasuredRun* run = nullptr;   ///< the data (owned by the caller)
  std::vector<std::string> channels;  ///< the motors compared (those with a JointAngle column)
  /// The accelerometer axes compared ("ABSR/AccelAxis1"), each residual times its weight: the angle sensor's noise
  /// over the axis's (deg per m/s²), so that both enter the loss in units of their own noise, scaled to degrees
  /// (docs/gap_measured_data.md, "Accelerometers").
  std::vector<std::string> accelerometers;
  std::vector<double> acceleration_weights;  ///< per accelerometer axis, deg per m/s²
  std::size_t samples = 0;            ///< (channels + accelerometer axes) × steps compared
  nlohmann::json scenario;            ///< the resolved scenario, without "log"
};

/// The replay of `run` on `rig` under `model` (noise off), with the run's firmware gain as /Servo/FirmwareKp and its
/// mean winding temperature, when the data has one, as /Servo/WindingTemperature.
/// Throws InputError naming the file and column when the run's agent, motors or time step do not fit the rig, or
/// when the model is the servo's and the run has no firmware gain.
ReplayRun MakeReplayRun(const Rig& rig, const MeasuredRun& run, const std::vector<ValueAssignment>& model);

/// The measured run as a recording (docs/recording.md) for orcs-view: the rig under `model` (noise off), posed
/// kinematically at every row — Reset(), the measured joint angles set (each clamped to its motor's range; motors
/// the run does not measure stay at 0), a frame stamped with the row's time. No physics runs: it shows where the
/// real robot's joints were. Returns the file's bytes.
std::string MeasuredRecording(const Rig& rig, const std::vector<ValueAssignment>& model, const ReplayRun& replay);

}  // namespace orcs::identify
