#include "model/evaluation/evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <new>
#include <thread>

#include "model/control/controller_factory.h"
#include "model/core/error.h"
#include "model/core/random_stream.h"
#include "model/core/text.h"
#include "model/core/value_logger.h"
#include "model/evaluation/recorder.h"
#include "model/evaluation/step_loop.h"
#include "model/fitness/fitness_function.h"
#include "model/scene/environment_reader.h"
#include "model/scene/parameter_sets.h"
#include "model/scene/simulation.h"
#include "model/script/script_sandbox.h"

namespace orcs::evaluation {
namespace {

using Clock = std::chrono::steady_clock;

// Wall-clock checks every this many steps: often enough to stop within a few ms, rarely enough to cost nothing.
constexpr int kStepsPerClockCheck = 64;
// A recording keeps at most this many frames (frame 0 and 60,000 steps: 10 simulated minutes at 10 ms, about 70 MB
// for the A-Series); a longer run's recording ends there, so that the recording's memory, and the result that
// carries it through the sandbox and the broker, stay bounded whatever the scenario's duration (≤ 1e6 s).
constexpr std::int64_t kMaxRecordedFrames = 60001;

scene::EnvironmentDescription EnvironmentOf(const scene::Scenario& scenario) {
  return scene::EnvironmentReader::ReadStringOrDefault(scenario.environment_xml, scenario.environment_name);
}

int FindScenarioAgent(const scene::Simulation& simulation, const scene::Scenario& scenario) {
  const int agent = simulation.FindAgent(scenario.agent);
  if (agent < 0) {
    throw InputError(scenario.source, 0, "field 'agent' names " + text::Quote(scenario.agent) + ", which the environment lacks");
  }
  return agent;
}

// Through the value's text form (shortest round trip: the same double), so that a drawn value is held to the
// value's range as every other writer is (a drawn /Simulation/TimeStepSize of 1e-300 is refused, not run).
void SetDrawn(VariableRepository& values, const std::string& path, double value) {
  const Value& target = values.Get(path);
  values.Set(path, target.type() == ValueType::kInt ? std::to_string(std::llround(value)) : text::FormatDouble(value));
}

// The environment's structure values — /Sim/Floor/Material, an object's /Sim/<name>/Material, Mass, size, ... —
// are read once, when the world is built. The scenario's values and the job's overrides that set them are
// therefore applied before the build as well as after it: else an override of the floor's material would change
// the repository but not the floor (a sweep over floor materials would sweep nothing).
void ApplyStructureValues(const std::vector<ValueAssignment>& assignments, VariableRepository& values) {
  std::vector<ValueAssignment> structure;
  for (const ValueAssignment& assignment : assignments) {
    if (assignment.path.starts_with("/Sim/") && values.Find(assignment.path) != nullptr) {
      structure.push_back(assignment);
    }
  }
  ValueFile::ApplyAssignments(structure, values);
}

// The scenario's values and the job's overrides, in that order, on a built world.
void ApplyJobValues(const EvaluationRequest& request, scene::Simulation& simulation) {
  ValueFile::ApplyAssignments(request.scenario.values, simulation.repository());
  ValueFile::ApplyAssignments(request.overrides, simulation.repository());
}

// A fresh world compiled from the scenario's environment, with the structure values the scenario and the job
// set, then all their values applied.
void BuildWorld(const EvaluationRequest& request, scene::Simulation& simulation) {
  simulation.LoadEnvironment(EnvironmentOf(request.scenario));
  ApplyStructureValues(request.scenario.values, simulation.repository());
  ApplyStructureValues(request.overrides, simulation.repository());
  simulation.Build();
  ApplyJobValues(request, simulation);
}

// A fresh world on the job's compiled model: what BuildWorld gives, without reading and compiling the
// environment again. Parameter sets apply their values after this; a set that changes a structure value (a
// link's mass) gets its own compiled world at its reset, the others share the job's.
void AttachWorld(const EvaluationRequest& request, std::shared_ptr<const scene::WorldModel> model,
                 scene::Simulation& simulation) {
  simulation.Attach(std::move(model));
  simulation.SetExcludedCollisionEvents(false);  // a job reads no events: same motion, fewer collision tests
  ApplyJobValues(request, simulation);
}

// Each schedule's path must name a number of the built world.
void CheckSchedules(const scene::Scenario& scenario, const VariableRepository& values) {
  for (const scene::ValueSchedule& schedule : scenario.schedules) {
    const Value* value = values.Find(schedule.path);
    if (value == nullptr || (value->type() != ValueType::kDouble && value->type() != ValueType::kInt)) {
      const std::string found =
          value == nullptr ? "no value of that path" : "a " + std::string(ValueTypeName(value->type()));
      throw InputError(scenario.source, 0,
                       "field 'schedules." + schedule.path + "' expected a number of the world, found " + found);
    }
  }
}

// Sets every schedule entry whose time has come by `time` (the start of the next step); `next` holds each
// schedule's first entry not yet set.
void ApplySchedules(const std::vector<scene::ValueSchedule>& schedules, double time, std::vector<std::size_t>& next,
                    VariableRepository& values) {
  constexpr double kClockSlack = 1e-9;  // s: the summed steps' rounding, far below a step
  for (std::size_t s = 0; s < schedules.size(); ++s) {
    const scene::ValueSchedule& schedule = schedules[s];
    std::size_t& k = next[s];
    bool due = false;
    while (k < schedule.times.size() && schedule.times[k] <= time + kClockSlack) {
      ++k;
      due = true;
    }
    if (due) SetDrawn(values, schedule.path, schedule.values[k - 1]);
  }
}

// Everything a set's run needs, built and configured; throws InputError for bad input.
struct SetRun {
  scene::Simulation simulation;
  int agent = -1;
  std::unique_ptr<control::Controller> controller;
  std::unique_ptr<fitness::FitnessFunction> fitness;
  std::unique_ptr<ValueLogger> logger;
};

// The scenario's "motor_model": the plug-in's model for every motor of the agent, in place of the Dynamixel model.
void SetPluginMotors(const scene::Scenario& scenario, const script::PluginRegistry* plugins, SetRun& run) {
  const std::string name = scenario.motor_model.at("plugin").get<std::string>();
  if (plugins == nullptr) throw script::PluginMissing("plug-in motor model '" + name + "': this process loads no plug-ins");
  const plugin::MotorModelFactory& factory = plugins->MotorModel(name);
  const std::string params = scenario.motor_model.value("params", nlohmann::json::object()).dump();
  aseries::ASeriesAgent& agent = run.simulation.agent(run.agent);
  std::vector<std::unique_ptr<plugin::MotorModel>> models;
  for (const std::string& motor : agent.motor_names()) {
    try {
      models.push_back(factory(params, motor));
    } catch (const std::invalid_argument& error) {
      throw InputError(scenario.source, 0, "field 'motor_model.params' expected params plug-in '" + name +
                                               "' accepts, found: " + error.what());
    }
    if (models.back() == nullptr) throw InputError(scenario.source, 0, "motor_model: plug-in '" + name + "' made nothing");
  }
  agent.SetPluginMotors(std::move(models));
}

void Configure(const EvaluationRequest& request, std::shared_ptr<const scene::WorldModel> model,
               const scene::ParameterSet* set, SetRun& run, SetOutcome& outcome) {
  const scene::Scenario& scenario = request.scenario;
  scene::Simulation& simulation = run.simulation;
  AttachWorld(request, std::move(model), simulation);
  if (set != nullptr) {
    if (set->parameter_file >= 0) {
      const scene::NamedParameterFile& file = scenario.randomisation.parameter_files[set->parameter_file];
      ValueFile::ApplyAssignments(file.assignments, simulation.repository());
      outcome.parameter_file = file.name;
    }
    for (const auto& [path, value] : set->values) SetDrawn(simulation.repository(), path, value);
    outcome.drawn = set->values;
  }
  run.agent = FindScenarioAgent(simulation, scenario);
  const control::ControlTarget target{scenario.agent, simulation.agent(run.agent).motor_names()};
  run.controller = control::MakeController(scenario.controller, request.genome, target, simulation, run.agent,
                                           scenario.source, request.plugins);
  run.fitness = std::make_unique<fitness::FitnessFunction>(scenario.fitness, simulation, run.agent, scenario.source,
                                                           request.plugins);
  if (!scenario.motor_model.is_null()) SetPluginMotors(scenario, request.plugins, run);
  if (!scenario.log.empty()) run.logger = std::make_unique<ValueLogger>(simulation.repository(), scenario.log);
  CheckSchedules(scenario, simulation.repository());
}

// The noise seed of set k: its own stream of the job's seed, so sets differ and jobs stay reproducible.
std::uint64_t SetSeed(std::uint64_t seed, int k) {
  return RandomStream(seed, "set-seed", static_cast<std::uint64_t>(k)).NextU64();
}

// The set's start pose: the joints posed about the agent's root, then the agent moved as a whole; what was
// drawn is reported as start_pose/x, /y, /z, /yaw_degrees, then start_pose/<motor> per motor.
void StartPose(const scene::ParameterSet& set, SetRun& run, SetOutcome& outcome) {
  scene::Simulation& simulation = run.simulation;
  if (!set.motor_angles_degrees.empty()) simulation.SetAgentJointAngles(run.agent, set.motor_angles_degrees);
  if (set.position_offset != Eigen::Vector3d::Zero() || set.yaw_degrees != 0.0) {
    simulation.MoveAgent(run.agent, set.position_offset, set.yaw_degrees);
    outcome.drawn.emplace_back("start_pose/x", set.position_offset.x());
    outcome.drawn.emplace_back("start_pose/y", set.position_offset.y());
    outcome.drawn.emplace_back("start_pose/z", set.position_offset.z());
    outcome.drawn.emplace_back("start_pose/yaw_degrees", set.yaw_degrees);
  }
  const std::vector<std::string>& motors = simulation.agent(run.agent).motor_names();
  for (std::size_t m = 0; m < set.motor_angles_degrees.size(); ++m) {
    outcome.drawn.emplace_back("start_pose/" + motors[m], set.motor_angles_degrees[m]);
  }
}

// The scenario's fixed start pose ("start_angles"): the named motors posed, the others left at the built pose. A
// drawn start pose (StartPose) then poses every motor again, so the two do not combine; scenarios use one or the
// other (a replay uses the fixed one).
void StartAngles(const scene::Scenario& scenario, SetRun& run) {
  const std::vector<std::string>& motors = run.simulation.agent(run.agent).motor_names();
  std::vector<double> degrees(motors.size(), 0.0);
  for (const auto& [motor, angle] : scenario.start_angles) {
    const auto found = std::find(motors.begin(), motors.end(), motor);
    if (found == motors.end()) {
      throw InputError(scenario.source, 0, "field 'start_angles." + motor + "' expected a motor of agent '" +
                                               scenario.agent + "', found none of that name");
    }
    degrees[static_cast<std::size_t>(found - motors.begin())] = angle;
  }
  run.simulation.SetAgentJointAngles(run.agent, degrees);
}

// A hang lasts this long, far beyond any time limit a test sets, and then stops by itself.
constexpr std::chrono::minutes kHangDuration{10};

// Keeps a core busy for `duration` (a volatile counter: the loop cannot be optimised away).
void Spin(Clock::duration duration) {
  const Clock::time_point end = Clock::now() + duration;
  volatile std::uint64_t turns = 0;
  while (Clock::now() < end) turns = turns + 1;
}

// The scenario's "fault", carried out (docs/scenarios.md "Fault injection"): the process dies or stops answering.
void InjectFault(const scene::FaultInjection& fault) {
  switch (fault.kind) {
    case scene::FaultInjection::Kind::kNone: return;
    case scene::FaultInjection::Kind::kSegfault: std::raise(SIGSEGV); return;
    case scene::FaultInjection::Kind::kAbort: std::abort();
    case scene::FaultInjection::Kind::kHang: std::this_thread::sleep_for(kHangDuration); return;
    case scene::FaultInjection::Kind::kSpin: Spin(kHangDuration); return;
  }
}

// "128 MiB" for whole mebibytes, else "N bytes".
std::string ByteCount(std::size_t bytes) {
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  return bytes % kMiB == 0 ? std::to_string(bytes / kMiB) + " MiB" : std::to_string(bytes) + " bytes";
}

// `log_bytes`: what the job's logs may still hold (kMaxJobLogBytes less the earlier sets' logs).
void Simulate(const EvaluationRequest& request, int k, const scene::ParameterSet* set, SetRun& run,
              SetOutcome& outcome, Clock::time_point deadline, std::size_t log_bytes) {
  scene::Simulation& simulation = run.simulation;
  simulation.Reset(SetSeed(request.seed, k));
  if (!request.scenario.start_angles.empty()) StartAngles(request.scenario, run);
  if (set != nullptr) StartPose(*set, run, outcome);
  run.controller->Reset();
  run.fitness->Start(simulation);
  if (run.logger) {
    run.logger->OpenInMemory({"orcs job log", "scenario: " + request.scenario.name,
                              "seed: " + std::to_string(request.seed), "parameter set: " + std::to_string(k)},
                             log_bytes,
                             "a job's logs hold at most " + ByteCount(request.max_log_bytes) +
                                 " over all its parameter sets; log fewer values or a shorter run");
    run.logger->Sample(simulation.time());
  }
  std::unique_ptr<Recorder> recorder;
  if (request.record_set == k) {
    recorder = std::make_unique<Recorder>(
        simulation, RecordingSource{request.program, request.scenario.environment_name, request.scenario.name,
                                    request.seed, k, request.genome});
  }
  const double dt = simulation.StepDuration();
  const auto steps = static_cast<std::int64_t>(std::llround(request.scenario.duration / dt));
  const bool fault = request.inject_faults && request.scenario.fault.kind != scene::FaultInjection::Kind::kNone;
  StepHooks hooks;
  std::vector<std::size_t> next_entry(request.scenario.schedules.size(), 0);
  hooks.drive = [&](std::int64_t i, double time) {
    if (fault && static_cast<std::uint64_t>(i) == request.scenario.fault.at_step) InjectFault(request.scenario.fault);
    ApplySchedules(request.scenario.schedules, time, next_entry, simulation.repository());
    run.controller->Update(time);
  };
  hooks.observe = [&](std::int64_t i) {
    run.fitness->Sample(simulation, dt);
    if (run.logger) run.logger->Sample(simulation.time());
    if (recorder && recorder->frame_count() < kMaxRecordedFrames) recorder->Sample();
    if (run.fitness->finished()) return false;  // a term says the rest cannot matter ("stop_above")
    if (i % kStepsPerClockCheck == 0 && Clock::now() > deadline) {
      outcome.status = EvaluationStatus::kTimeout;
      outcome.message = "time limit of " + text::FormatDouble(request.time_limit_seconds) +
                        " s exceeded in parameter set " + std::to_string(k) + " at simulated time " +
                        text::FormatDouble(simulation.time()) + " s";
      return false;
    }
    return true;
  };
  RunSteps(simulation, steps, hooks);
  if (simulation.status() != scene::SimulationStatus::kOk) {
    outcome.status = EvaluationStatus::kUnstablePhysics;
    outcome.message = "parameter set " + std::to_string(k) + ": " + simulation.message();
  }
  outcome.simulated_seconds = simulation.time();
  outcome.terms = run.fitness->terms();
  outcome.fitness = run.fitness->fitness();
  if (outcome.status == EvaluationStatus::kOk && !std::isfinite(outcome.fitness)) {
    outcome.status = EvaluationStatus::kUnstablePhysics;
    outcome.message = "parameter set " + std::to_string(k) + ": the fitness is not finite";
  }
  if (run.logger) {
    run.logger->Finish();
    outcome.log_csv = run.logger->TakeText();
  }
  if (recorder) outcome.recording = recorder->Finish();
}

// A script of set k failed (its error, or a limit): the set ends with the script's status and one line.
void ScriptFailed(const script::ScriptFailure& failure, int k, const SetRun& run, SetOutcome& outcome) {
  outcome.status = failure.kind() == script::ScriptFailure::Kind::kLimit ? EvaluationStatus::kScriptLimit
                                                                         : EvaluationStatus::kScriptError;
  outcome.message = "parameter set " + std::to_string(k) + ": " + failure.what();
  outcome.simulated_seconds = run.simulation.built() ? run.simulation.time() : 0.0;
  outcome.terms.clear();
  outcome.fitness = 0.0;
}

// The job's world, compiled once, and its parameter sets, drawn against the nominal world (scenario values and
// overrides applied).
struct JobWorld {
  std::shared_ptr<const scene::WorldModel> model;  ///< compiled from the environment and the structure values
  std::vector<scene::ParameterSet> sets;            ///< one per parameter set, in order
};

JobWorld PrepareJob(const EvaluationRequest& request) {
  scene::Simulation nominal;
  BuildWorld(request, nominal);
  // A missing agent draws no motor angles here and fails in Configure, with the scenario's field named.
  const int agent = nominal.FindAgent(request.scenario.agent);
  const std::vector<aseries::MorphologyMotor> no_motors;
  return {nominal.shared_model(),
          scene::DrawParameterSets(request.scenario.randomisation, request.seed, nominal.repository(),
                                   agent < 0 ? no_motors : nominal.model().morphology(agent).motors,
                                   request.scenario.source)};
}

}  // namespace

std::string_view EvaluationStatusName(EvaluationStatus status) {
  switch (status) {
    case EvaluationStatus::kOk: return "ok";
    case EvaluationStatus::kInvalidInput: return "invalid input";
    case EvaluationStatus::kUnstablePhysics: return "unstable physics";
    case EvaluationStatus::kTimeout: return "timeout";
    case EvaluationStatus::kInternalError: return "internal error";
    case EvaluationStatus::kScriptError: return "script error";
    case EvaluationStatus::kScriptLimit: return "script limit";
    case EvaluationStatus::kPluginMissing: return "plugin missing";
  }
  return "?";
}

void CheckRequest(const EvaluationRequest& request) {
  const JobWorld job = PrepareJob(request);
  SetRun run;
  SetOutcome outcome;
  try {
    Configure(request, job.model, job.sets.empty() ? nullptr : &job.sets.front(), run, outcome);
  } catch (const script::ScriptFailure& failure) {  // a script's top level failed: the job cannot run as given
    throw InputError(failure.what());
  } catch (const script::PluginMissing&) {  // whether a worker has the plug-in, only the worker knows
    if (request.plugins != nullptr) throw;
  }
}

control::ControlTarget ControlTargetOf(const scene::Scenario& scenario) {
  scene::Simulation simulation;
  simulation.LoadEnvironment(EnvironmentOf(scenario));
  simulation.Build();
  return {scenario.agent, simulation.agent(FindScenarioAgent(simulation, scenario)).motor_names()};
}

EvaluationOutcome Evaluate(const EvaluationRequest& request) {
  const Clock::time_point start = Clock::now();
  const double limit = request.time_limit_seconds;
  const Clock::time_point deadline =
      limit > 0 && limit <= kMaxJobTimeLimitSeconds
          ? start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit))
          : Clock::time_point::max();
  EvaluationOutcome outcome;
  try {
    if (!(limit >= 0 && limit <= kMaxJobTimeLimitSeconds)) {  // NaN fails both
      throw InputError("time limit", 0,
                       "expected seconds from 0 (none) to " + text::FormatDouble(kMaxJobTimeLimitSeconds) +
                           ", found " + text::FormatDouble(limit));
    }
    const JobWorld job = PrepareJob(request);
    std::size_t log_bytes = request.max_log_bytes;
    for (int k = 0; k < static_cast<int>(job.sets.size()); ++k) {
      SetOutcome set_outcome;
      set_outcome.index = k;
      SetRun run;
      try {
        Configure(request, job.model, &job.sets[k], run, set_outcome);
        Simulate(request, k, &job.sets[k], run, set_outcome, deadline, log_bytes);
      } catch (const script::ScriptFailure& failure) {
        ScriptFailed(failure, k, run, set_outcome);
      }
      outcome.engine = run.simulation.engine();  // after its reset: the engine the job's values chose
      log_bytes -= std::min(log_bytes, set_outcome.log_csv.size());
      outcome.sets.push_back(std::move(set_outcome));
      if (outcome.sets.back().status != EvaluationStatus::kOk) {
        outcome.status = outcome.sets.back().status;
        outcome.message = outcome.sets.back().message;
        break;
      }
    }
  } catch (const InputError& error) {
    outcome.status = EvaluationStatus::kInvalidInput;
    outcome.message = error.what();
  } catch (const script::PluginMissing& missing) {
    outcome.status = EvaluationStatus::kPluginMissing;
    outcome.message = missing.what();
  } catch (const std::bad_alloc&) {
    throw;  // the process's trouble, not the job's: its caller says which memory ran out
  } catch (const std::exception& error) {
    outcome.status = EvaluationStatus::kInternalError;
    outcome.message = error.what();
  }
  if (outcome.status == EvaluationStatus::kOk) {
    std::vector<double> values;
    for (const SetOutcome& set : outcome.sets) values.push_back(set.fitness);
    outcome.fitness = scene::AggregateFitness(values, request.scenario.aggregate, request.scenario.quantile);
  }
  outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return outcome;
}

}  // namespace orcs::evaluation
