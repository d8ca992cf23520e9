// orcs-sim: the headless local simulator. Builds a world from an ORCS XML environment and value files, runs it
// for a given simulated time and logs repository values to CSV (docs/orcs-sim.md).
#include <algorithm>
#include <chrono>
#include <csignal>
#include <limits>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "model/control/keyframe_player.h"
#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/rotation.h"
#include "model/core/text.h"
#include "model/core/value_file.h"
#include "model/core/value_logger.h"
#include "model/evaluation/recorder.h"
#include "model/evaluation/step_loop.h"
#include "model/physics/mujoco/mjcf_export.h"
#include "model/scene/environment_reader.h"
#include "model/scene/simulation.h"
#include "model/scene/world_setup.h"
#include "net/cli_style.h"
#include "worker/osp/protocol_values.h"
#include "worker/played_records.h"
#include "worker/sim/gui_launch.h"
#include "worker/sim/realtime.h"
#include "worker/sim/scenario_run.h"
#include "worker/sim/sim_options.h"

namespace orcs::sim {
namespace {

void PrintValues(const VariableRepository& repository, const std::string& regular_expression) {
  for (int id : repository.Match(regular_expression)) {
    std::cout << repository.path(id) << "=" << repository.value(id).ToString() << "\n";
  }
}

// Every body (name, mass, shape, size), joint (name, type, range in degrees) and agent, as JSON.
nlohmann::json Describe(const scene::Simulation& simulation) {
  const physics::PhysicsModel& model = *simulation.model().physics();
  nlohmann::json bodies = nlohmann::json::array();
  for (int b = 0; b < model.body_count(); ++b) {
    const physics::BodyDescription& body = model.body(b);
    bodies.push_back({{"name", body.name},
                      {"dynamic", body.dynamic},
                      {"mass", model.total_mass(b)},
                      {"shape", evaluation::ShapeName(body.geoms.front().shape)},
                      {"size", evaluation::GeomSizeJson(body.geoms.front())},
                      {"material", body.geoms.front().material},
                      {"geoms", body.geoms.size()}});
  }
  nlohmann::json joints = nlohmann::json::array();
  for (int j = 0; j < model.joint_count(); ++j) {
    const physics::JointDescription& joint = model.joint(j);
    nlohmann::json entry = {{"name", joint.name},
                            {"type", joint.type == physics::JointType::kHinge ? "hinge" : "fixed"},
                            {"body1", joint.body1},
                            {"body2", joint.body2}};
    if (joint.limited) entry["range"] = {RadiansToDegrees(joint.lo), RadiansToDegrees(joint.hi)};
    joints.push_back(entry);
  }
  nlohmann::json agents = nlohmann::json::array();
  const std::vector<scene::AgentDescription>& agent_descriptions = simulation.model().environment().agents;
  for (size_t a = 0; a < agent_descriptions.size(); ++a) {
    const scene::AgentDescription& agent = agent_descriptions[a];
    const aseries::ASeriesLayout& layout = simulation.model().agents()[a];
    nlohmann::json motors = nlohmann::json::array();
    for (int joint : layout.motors) {
      const physics::JointDescription& motor = model.joint(joint);
      motors.push_back({{"name", motor.name.substr(agent.name.size() + 1)},
                        {"range", {RadiansToDegrees(motor.lo), RadiansToDegrees(motor.hi)}}});
    }
    double mass = 0.0;
    for (int body : layout.bodies) mass += model.total_mass(body);
    agents.push_back({{"name", agent.name},
                      {"type", agent.type},
                      {"position", {agent.position.x(), agent.position.y(), agent.position.z()}},
                      {"mass", mass},
                      {"motors", motors}});
  }
  return {{"environment", simulation.model().environment().source},
          {"bodies", bodies},
          {"joints", joints},
          {"agents", agents}};
}

std::vector<std::string> LogComments(const SimOptions& options) {
  return {"orcs-sim log", "environment: " + (options.environment.empty() ? "(none)" : options.environment),
          "seed: " + std::to_string(options.seed), "duration: " + text::FormatDouble(options.duration) + " s"};
}


// The original's pause after each step, ms (0: none); ignored under --realtime, which paces to the wall clock.
constexpr std::string_view kDelayPath = "/Simulation/Delay";
constexpr double kLongestDelayMs = 3.6e6;  // an hour per step: anything longer is a slip

volatile std::sig_atomic_t stop_requested = 0;
extern "C" void OnStopSignal(int) { stop_requested = 1; }

// The original ran until stopped: so does orcs-sim serving ODCP without --duration.
bool UntilStopped(const SimOptions& options) { return options.odcp_port >= 0 && !options.duration_given; }

// --duration in steps. Checks /Simulation/TimeStepSize and IterationsPerStep: a non-positive value would
// silently give no steps.
std::int64_t StepCount(const SimOptions& options, scene::Simulation& simulation) {
  const double step_count = options.duration / simulation.StepDuration();
  if (!(step_count < 1e15)) {  // NaN (CLI11's NonNegativeNumber lets "nan" through) or beyond llround's range
    throw InputError("--duration", 0,
                     "expected seconds that take fewer than 1e15 steps, found " +
                         text::FormatDouble(options.duration) + " (" + text::FormatDouble(step_count) + " steps)");
  }
  return static_cast<std::int64_t>(std::llround(step_count));
}

double DelaySeconds(const VariableRepository& repository) {
  const double ms = repository.Get(kDelayPath).as_double();
  if (!(ms >= 0.0 && ms <= kLongestDelayMs)) {
    throw InputError(std::string(kDelayPath), 0,
                     "expected milliseconds between 0 and " + text::FormatDouble(kLongestDelayMs) + ", found " +
                         text::FormatDouble(ms));
  }
  return ms / 1000.0;
}

void PrintSummary(const scene::Simulation& simulation, double wall_seconds) {
  const double factor = wall_seconds > 0 ? simulation.time() / wall_seconds : INFINITY;
  std::printf("simulated %.3f s in %lld steps, wall time %.3f s, real-time factor %.1f\n", simulation.time(),
              static_cast<long long>(simulation.steps()), wall_seconds, factor);
}

int Run(const SimOptions& options) {
  scene::Simulation simulation;
  osp::AddProtocolValues(simulation.repository());  // -port's ODCP switch, settable by -val as in the original
  simulation.repository().Add(kDelayPath, 0.0);
  const IgnoredValues ignored = scene::SetUpWorld(simulation, options.environment, options.initial_value_files,
                                                  options.value_files, options.strict ? UnknownPaths::kRefuse : UnknownPaths::kIgnore);
  if (!ignored.empty()) std::cerr << "orcs-sim: " << ignored.Warning() << "\n";
  if (!options.engine.empty()) simulation.repository().Set("/Simulation/Engine", options.engine);  // Reset remakes
  simulation.Reset(options.seed);
  std::vector<control::KeyframePlayer> players = MakePlayers(options.play, simulation, "orcs-sim");

  if (!options.print_values.empty()) {
    PrintValues(simulation.repository(), options.print_values);
    return cli::kExitOk;
  }
  if (options.describe) {
    std::cout << Describe(simulation).dump(2) << "\n";
    return cli::kExitOk;
  }
  if (!options.export_robot.empty()) {
    if (simulation.agent_count() == 0) throw InputError("--export-robot", 0, "the environment has no robot to write");
    AtomicFile file(options.export_robot);
    file.stream() << aseries::WriteASeriesMorphology(
        simulation.model().morphology(0),
        {"Robot " + simulation.agent(0).name() + " of " + simulation.model().environment().source +
         ", written by orcs-sim --export-robot with the value files' changes applied."});
    file.Commit();
    return cli::kExitOk;
  }
  if (!options.export_mjcf.empty()) {
    AtomicFile file(options.export_mjcf);
    file.stream() << physics::ExportMjcf(*simulation.model().physics(), {.exclusions = true});
    file.Commit();
    return cli::kExitOk;
  }

  const std::int64_t steps = UntilStopped(options) ? std::numeric_limits<std::int64_t>::max() : StepCount(options, simulation);
  const double delay_seconds = DelaySeconds(simulation.repository());

  std::unique_ptr<ValueLogger> logger;
  if (!options.log.empty()) {
    logger = std::make_unique<ValueLogger>(simulation.repository(), options.log);
    logger->Open(options.out, LogComments(options));
    logger->Sample(simulation.time());
  }
  std::unique_ptr<evaluation::Recorder> recorder;
  if (!options.record.empty()) {
    recorder = std::make_unique<evaluation::Recorder>(
        simulation, evaluation::RecordingSource{"orcs-sim", options.environment, "", options.seed, 0, nullptr});
  }
  std::unique_ptr<RealtimeRunner> pacer;  // the wall clock, the delay and ODCP
  if (options.realtime || options.odcp_port >= 0 || delay_seconds > 0.0) {
    pacer = std::make_unique<RealtimeRunner>(simulation, options.odcp_port, options.bind_address);
    pacer->PrintEndpoints(std::cout);
  }
  if (UntilStopped(options)) {
    std::signal(SIGINT, OnStopSignal);
    std::signal(SIGTERM, OnStopSignal);
    std::cerr << "orcs-sim: running until stopped (Ctrl-C or SIGTERM); --duration S ends it after S simulated "
                 "seconds\n";
  }
  const auto start = std::chrono::steady_clock::now();
  evaluation::StepHooks hooks;
  hooks.drive = [&](std::int64_t i, double time) {
    if (pacer && options.realtime) pacer->WaitForStep(i, simulation.StepDuration());
    if (pacer && !options.realtime) pacer->Pause(delay_seconds);  // the original's delay after each step
    for (control::KeyframePlayer& player : players) player.Apply(time);
  };
  hooks.observe = [&](std::int64_t) {
    if (logger) logger->Sample(simulation.time());
    if (recorder) recorder->Sample();
    return stop_requested == 0;
  };
  evaluation::RunSteps(simulation, steps, hooks);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (logger) logger->Finish();
  if (recorder) evaluation::WriteRecording(options.record, recorder->Finish());
  PrintSummary(simulation, wall);
  if (simulation.status() != scene::SimulationStatus::kOk) {
    std::cerr << "orcs-sim: " << simulation.message() << "\n";
    return cli::kExitRunFailed;
  }
  return cli::kExitOk;
}

}  // namespace
}  // namespace orcs::sim

int main(int argc, char** argv) {
  return orcs::cli::RunProgram("orcs-sim", orcs::sim::ParseSimOptions(argc, argv), [&](const auto& options) {
    if (options.gui) return orcs::sim::LaunchGui(argv[0], options);
    if (!options.scenario.empty()) return orcs::sim::RunScenario(options);
    return orcs::sim::Run(options);
  });
}
