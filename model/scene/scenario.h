// A scenario (docs/scenarios.md): what one evaluation runs — the world, value overrides, the duration, the
// controller and how a genome maps onto it, the fitness terms, the randomisation and what to log. Description
// layer, read from JSON (nlohmann-json).
//
// A scenario file may reference other files (the environment XML, value files, motion records) relative to
// itself. ResolveScenarioFile inlines every one of them, so that the resolved JSON is self-contained: that is
// what a client puts into a job, and a worker needs no shared filesystem. ParseScenario reads resolved JSON
// only. The controller and fitness sections are kept as JSON here and checked by model/control and
// model/fitness (the layer rule: scene does not know them).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "model/core/value_file.h"

namespace orcs {
class JsonNode;
}  // namespace orcs

namespace orcs::scene {

/// How one repository value varies between parameter sets.
struct ParameterDistribution {
  enum class Kind { kUniform, kNormal };
  std::string path;             ///< repository path of a number (checked against the built world); "" with `match`
  Kind kind = Kind::kUniform;   ///< distribution
  double low = 0.0;             ///< uniform: lower bound; normal: lower clamp (−inf = none)
  double high = 0.0;            ///< uniform: upper bound; normal: upper clamp (+inf = none)
  double mean = 0.0;            ///< normal: mean
  double deviation = 0.0;       ///< normal: standard deviation, ≥ 0
  bool relative = false;        ///< true: low/high/mean/deviation are factors of the value's nominal value
  /// Instead of `path`: a regular expression (RE2, whole path) naming many numbers, each drawn on its own from
  /// this distribution, in registration order — "/Sim/Humanoid/.*/Mass" with relative [0.95, 1.05] varies each
  /// link's mass by up to ±5 %. "" with `path`.
  std::string match;
};

/// A named value file offered to the parameter sets (inlined: its assignments).
struct NamedParameterFile {
  std::string name;                            ///< the file name as given in the scenario
  std::vector<ValueAssignment> assignments;    ///< its lines, includes flattened
};

/// Start-pose randomisation of the scenario's agent, per parameter set.
struct StartPoseRandomisation {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< ± uniform offset per axis of the agent, m (y: 0…+y only)
  double yaw_degrees = 0.0;           ///< ± uniform turn of the agent about the vertical through its origin, degrees
  double motor_angle_degrees = 0.0;   ///< ± uniform initial angle of every motor (clamped to its range), degrees
};

/// How a job's fitness aggregates over its parameter sets.
enum class Aggregate { kMean, kMin, kMax, kQuantile };

/// Bounds of the counts a scenario gives (docs/scenarios.md, "Limits"): each costs memory and time in proportion to
/// a small number in the file, so each is held to a documented maximum and refused naming its field.
inline constexpr int kMaxParameterSets = 10000;                 ///< randomisation.sets
inline constexpr std::size_t kMaxRandomisedParameters = 1000;   ///< randomisation.parameters (with the defaults)
inline constexpr std::size_t kMaxDrawnValues = 100000;          ///< sets × parameters: the values a job draws
inline constexpr std::size_t kMaxLogPatterns = 1000;            ///< log

struct Randomisation {
  int sets = 1;                                  ///< K parameter sets per job, 1…kMaxParameterSets
  std::vector<ParameterDistribution> parameters;  ///< varied values, in the scenario's order
  std::vector<NamedParameterFile> parameter_files;  ///< value files, one chosen per set
  bool files_in_sequence = false;                ///< true: set k takes file k mod n; false: one at random
  StartPoseRandomisation start_pose;             ///< start-pose offsets
};

/// A reliability-test hook (docs/scenarios.md "Fault injection"): the job crashes or hangs the process that
/// simulates it. Honoured only inside orcs-worker's sandboxed simulation process; everywhere else it is ignored.
struct FaultInjection {
  enum class Kind { kNone, kSegfault, kAbort, kHang, kSpin };
  /// What happens: raise(SIGSEGV), abort(), a sleep that ignores the time limit, or a busy loop that ignores it
  /// (spends CPU time, as an engine stuck in a loop does).
  Kind kind = Kind::kNone;
  std::uint64_t at_step = 0;  ///< before which simulation step of each parameter set it happens (0-based)
};

/// One value of the world set during a run ("schedules": {"<path>": {"times": [s, ...], "values": [...]}}): values[k]
/// is set before the first step that starts at or after times[k] and holds until the next entry.
struct ValueSchedule {
  std::string path;            ///< repository path of a number (e.g. /Servo/SupplyVoltage)
  std::vector<double> times;   ///< s since the reset, non-decreasing
  std::vector<double> values;  ///< in the value's unit, one per time
};

struct Scenario {
  std::string source;            ///< where it was read from, for messages
  /// a label for reports, and the default output folder runs/<name>: text::NameProblem finds nothing in it
  std::string name;
  std::string environment_xml;   ///< the ORCS XML environment, inline; "" = one A-Series "Humanoid" on the floor
  std::string environment_name;  ///< the environment file's name, for messages ("(default)" when none)
  std::vector<ValueAssignment> values;  ///< applied after the world is built, before each parameter set's values
  double duration = 10.0;        ///< simulated seconds per parameter set
  std::string agent = "Humanoid";  ///< the agent the controller drives and the fitness terms measure
  nlohmann::json controller;     ///< controller section (model/control/controller_factory.h)
  nlohmann::json fitness;        ///< fitness section (model/fitness/fitness_function.h)
  /// "motor_model": {"plugin": "<plug-in>/<component>", "params": {...}}: a worker's plug-in motor model in place of
  /// the Dynamixel model for every motor of the agent (docs/extending.md, "Plug-ins"); null = the built-in model.
  nlohmann::json motor_model;
  Aggregate aggregate = Aggregate::kMean;  ///< over the parameter sets
  double quantile = 0.5;         ///< for Aggregate::kQuantile, 0…1
  Randomisation randomisation;
  /// "start_angles": motor name → degrees, the pose every parameter set starts in (before a drawn start pose is
  /// added): a replay of a measured run starts where the real joint was. Empty = the built pose.
  std::vector<std::pair<std::string, double>> start_angles;
  /// "schedules": values of the world that change during the run, each set from its times on (a replay's measured
  /// supply voltage). Empty = none.
  std::vector<ValueSchedule> schedules;
  std::vector<std::string> log;  ///< regular expressions of values logged every step ([] = no log)
  nlohmann::json genome;         ///< "genome": the genome of a job that brings none (flat array or network); null = none
  FaultInjection fault;          ///< "fault": a test hook for crash isolation; kind kNone = none
  /// "evolution": how orcs-batch evolve searches the genome (bounds, algorithm, ...; docs/evolution.md). Read and
  /// checked by the client (clients/evolve); a job carries it but the model never reads it. null = none
  nlohmann::json evolution;
  /// "record": orcs-batch asks a recording (docs/recording.md) of every job of the scenario, parameter set 0. Read by
  /// the client, which sets Job.record; the model and the worker never act on it.
  bool record = false;
};

/// The wall-clock time limit of a job running `scenario` when its user gave none, s: 30 s + 10 s per simulated
/// second over all parameter sets (a standing A-Series runs 11× faster than real time on one core, so this
/// leaves 100× for slow or busy machines). Every job the clients send carries a limit (docs/protocol.md, "Leases").
double DefaultTimeLimitSeconds(const Scenario& scenario);
/// The same for a job simulating `simulated_seconds` in all.
double DefaultTimeLimitSeconds(double simulated_seconds);

/// Parses a resolved scenario (no file references). Throws InputError "source: field 'a.b' expected ..., found
/// ..." for unknown keys, wrong types, min above max, a non-positive duration or set count, a count beyond its
/// bound above, a name that is not a plain label (text::NameProblem), ...
Scenario ParseScenario(const nlohmann::json& resolved, const std::string& source);

/// The assignments of a "values" object, {"/path": 1.5, "/flag": true, "/name": "PVC"}: numbers printed so that
/// they read back to the same double, booleans T/F, strings as they are; each named after its field for messages.
/// Throws InputError for a value of another type. A scenario's "values", and a regression case's (docs/regress.md).
std::vector<ValueAssignment> ParseInlineValues(const JsonNode& node);

/// Reads a scenario file and inlines every file it references (relative to the file's folder):
/// "environment": "x.xml" → {"file": "x.xml", "xml": text}; "value_files" and
/// "randomisation.parameter_files.files" → {"file", "assignments"}; any member named "record" or "script" holding a
/// file name in the controller or fitness sections → {"file", "text"}. Throws InputError naming the scenario field
/// and the file that cannot be read.
nlohmann::json ResolveScenarioFile(const std::string& path);

/// Puts a resolved scenario's world on `engine` (one of EngineNames()): "/Simulation/Engine" in its "values",
/// replacing the scenario's own choice. What the --engine option of orcs-sim and orcs-batch does.
void SetScenarioEngine(nlohmann::json& resolved, const std::string& engine);

/// The aggregate of per-set fitness values (not empty). Quantiles interpolate linearly between order
/// statistics (type 7).
double AggregateFitness(std::vector<double> values, Aggregate aggregate, double quantile);

}  // namespace orcs::scene
