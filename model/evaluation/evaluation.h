// One job, evaluated: a scenario with a genome and a seed, under the scenario's K randomised parameter sets.
// This is the model's view of a job (no protobuf): orcs-worker translates wire jobs into EvaluationRequests
// and outcomes into results; orcs-sim and the clients' input checks use it directly.
//
// The job's world is compiled once, from the scenario's environment with the structure values — /Sim/Floor/Material,
// /Sim/<object>/... — that the scenario's values and the job's overrides set (parameter sets cannot change the
// structure: their values come after it). For every parameter set k: a fresh state on that model; the
// scenario's values, the job's overrides, the set's value file and drawn values, in that order; Reset with the
// set's seed; the start pose; then duration / step steps of: controller → step → fitness sample (→ log row). Set
// k's noise seed and draws come from the job's seed alone, so the outcome is the same bits on any worker.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "model/control/controller_factory.h"
#include "model/core/value_file.h"
#include "model/scene/scenario.h"
#include "model/script/plugin_registry.h"

namespace orcs::evaluation {

/// The longest wall-clock time limit a job may carry (31 years: the default limit of a job of 1e8 simulated
/// seconds); beyond it, and for NaN, infinity or a negative limit, the job is invalid input. A deadline computed
/// from a larger limit would overflow the clock (an infinite limit timed out at once).
inline constexpr double kMaxJobTimeLimitSeconds = 1e9;
/// A job's logs (scenario "log"), all parameter sets together, hold at most this many bytes of CSV (128 MiB): a log
/// that would grow past it ends with a "# log truncated ..." line, so that a job's memory, and the result that
/// carries its logs through the sandbox and the broker (512 MiB per message), stay bounded.
inline constexpr std::size_t kMaxJobLogBytes = std::size_t{128} << 20;

struct EvaluationRequest {
  scene::Scenario scenario;                 ///< parsed, resolved
  nlohmann::json genome = nlohmann::json::array();  ///< flat numbers, or a full network object
  std::uint64_t seed = 0;                   ///< the job's seed
  std::vector<ValueAssignment> overrides;   ///< applied after the scenario's values
  double time_limit_seconds = 0.0;          ///< wall-clock limit for the whole job, s; 0 = none; ≤ kMaxJobTimeLimitSeconds
  /// Whether the scenario's "fault" test hook is carried out. Only orcs-worker's sandboxed simulation process sets
  /// it (worker/job/sandbox_child.h): a fault anywhere else would take a user's program down with it.
  bool inject_faults = false;
  /// Record parameter set `record_set`'s run (docs/recording.md) into SetOutcome::recording; −1 = record none.
  /// Recording only reads the simulation: the outcome's numbers are the same bits either way.
  int record_set = -1;
  std::string program = "orcs";  ///< who runs the job, written into recordings
  /// Bound on the job's logs, bytes of CSV over all parameter sets (see kMaxJobLogBytes, the default).
  std::size_t max_log_bytes = kMaxJobLogBytes;
  /// The plug-in components this process loaded (orcs-worker --plugins DIR), for "plugin" controllers and terms;
  /// null = none. CheckRequest accepts a job naming plug-ins without one: only the worker knows what it has.
  const script::PluginRegistry* plugins = nullptr;
};

/// How a job (or a parameter set) ended. kScriptError: a script of the job raised or made an error while it ran;
/// kScriptLimit: a script reached its instruction budget or memory cap (docs/extending.md). A script that does not
/// compile, or fails in its top level, makes the job kInvalidInput: that is found before any simulation.
/// kPluginMissing: the job names a plug-in component this process has not loaded (docs/extending.md, "Plug-ins").
enum class EvaluationStatus {
  kOk, kInvalidInput, kUnstablePhysics, kTimeout, kInternalError, kScriptError, kScriptLimit, kPluginMissing
};
std::string_view EvaluationStatusName(EvaluationStatus status);

/// One parameter set's run.
struct SetOutcome {
  int index = 0;                                        ///< k
  std::vector<std::pair<std::string, double>> drawn;    ///< drawn values (paths; "start_pose/x", ... for the pose)
  std::string parameter_file;                           ///< the value file chosen for the set, "" = none
  std::vector<std::pair<std::string, double>> terms;    ///< fitness terms, scenario order
  double fitness = 0.0;                                 ///< Σ weight · term
  EvaluationStatus status = EvaluationStatus::kOk;
  std::string message;                                  ///< why, when not ok
  double simulated_seconds = 0.0;                       ///< simulated time reached
  std::string log_csv;                                  ///< the logged values (scenario "log"), "" = none
  std::string recording;                                ///< the run's recording file bytes, "" = not recorded
};

struct EvaluationOutcome {
  EvaluationStatus status = EvaluationStatus::kOk;  ///< the first failing set's status, else ok
  std::string message;                              ///< the first failing set's message
  double fitness = 0.0;                             ///< aggregate over the sets (only when ok)
  std::vector<SetOutcome> sets;
  std::string engine;  ///< /Simulation/Engine of the job's world ("ODE", "MuJoCo"); "" when it was not built
  double wall_seconds = 0.0;                        ///< time the evaluation took (not part of the bits)
};

/// Runs a job. Never throws for bad input: an InputError becomes kInvalidInput with its message. std::bad_alloc
/// passes through: running out of memory is the process's trouble, not the job's (worker/job/job_translation.h).
EvaluationOutcome Evaluate(const EvaluationRequest& request);

/// Checks a job without simulating it — what a client does before it submits: builds the world, draws the
/// parameter sets and sets up the first set's controller, fitness and log, so that every error a worker would
/// report as invalid input is thrown here as the same InputError.
void CheckRequest(const EvaluationRequest& request);

/// The agent a scenario's controller drives, with its motors: what control::CheckGenome checks genomes against.
/// Builds the scenario's world; throws InputError for a bad environment or an agent it lacks.
control::ControlTarget ControlTargetOf(const scene::Scenario& scenario);

}  // namespace orcs::evaluation
