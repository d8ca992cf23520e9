// One simulation: a shared, immutable WorldModel plus this run's state — the variable repository, the events,
// the physics world, the time (MuJoCo's mjModel/mjData split; Drake's System/Context).
//
// Life cycle, as the original's -ival/-val options expect:
//   Simulation sim;                        // registers /Simulation/... and /MaterialProperties/... values
//   sim.LoadEnvironment(environment);      // registers /Sim/<object>/... values
//   ValueFile::Apply(ival, sim.repository());   // initial values: may change the structure
//   sim.Build();                           // compiles the model and creates the physics world
//   ValueFile::Apply(val, sim.repository());    // run-time values
//   sim.Reset(seed);  while (...) sim.Step();
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "model/aseries/aseries_agent.h"
#include "model/core/event_manager.h"
#include "model/core/variable_repository.h"
#include "model/physics/physics_world.h"
#include "model/scene/agent_posing.h"
#include "model/scene/world_model.h"

namespace orcs::scene {

/// How a run stands. Anything but kOk is final until the next Reset().
enum class SimulationStatus {
  kOk,
  kUnstable,     ///< non-finite or exploding state (physics::StepStatus::kUnstable)
  kEngineError,  ///< the physics engine reported an error; see message()
};

std::string_view SimulationStatusName(SimulationStatus status);

/// The range of /Simulation/TimeStepSize, seconds (docs/orcs-sim.md): a value outside it is refused where it is
/// written (value files, scenario values, job overrides, sweeps, OSP command 52).
inline constexpr double kMinTimeStep = 1e-5;
inline constexpr double kMaxTimeStep = 0.1;

class Simulation {
 public:
  Simulation();
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Registers the environment's object values. Before Build().
  void LoadEnvironment(const EnvironmentDescription& environment);
  /// Compiles the model from the repository and creates the world in its initial state. Throws InputError.
  void Build();
  /// Uses an already compiled model (shared between simulations); registers its object values. Instead of
  /// LoadEnvironment() + Build().
  void Attach(std::shared_ptr<const WorldModel> model);

  /// Back to the initial state: time 0, initial poses, no contacts; `seed` is published as /Simulation/Seed.
  /// Structure values written since the world was compiled (a mass, a size, a material, an object's start pose;
  /// WorldModel::StructureValue) apply here: the world is compiled again from the repository and made anew, so
  /// such a write is never lost. Throws InputError when the new values cannot be compiled; the old world stays.
  void Reset(std::uint64_t seed = 0);

  /// Object Properties' "set as initial": object `name`'s pose now becomes its start pose at the next Reset and
  /// after (as if its Position and Orientation had been written from outside). Throws InputError naming `name`
  /// when it is no object of the environment: a robot starts where its agent is placed.
  void KeepPoseAsStart(const std::string& name);

  /// Moves agent `index` rigidly, right after Reset(): turned by `yaw_degrees` about the vertical through its
  /// placement position, then shifted by `offset` (m) — start-pose randomisation. Its sensors restart there.
  void MoveAgent(int index, const Eigen::Vector3d& offset, double yaw_degrees);

  /// Poses agent `index`'s joints, right after Reset() and before or after MoveAgent(): motor m's hinge is turned
  /// to `degrees[m]` (motor order, each within the motor's MinAngle…MaxAngle) by turning the bodies on its far
  /// side from the agent's root about the hinge's line, from the root outward (model/scene/agent_posing.h). The
  /// root — the static world for a held agent or the pendulum rig, else the morphology's root body (the
  /// A-Series pelvis) — stays where it is; velocities stay zero. Angles are the hinge angles relative to the
  /// initial pose, so JointAngle then reads `degrees` (before noise). Its sensors and motors restart there.
  void SetAgentJointAngles(int index, const std::vector<double>& degrees);

  /// Whether pairs on the exclusion list still raise their bodies' collision events, as in the original
  /// (spec/aseries.md §3b; the default). They make no contact either way: off gives the same motion bit for bit
  /// and saves their collision tests, for callers that read no events (batch jobs, replays). Stays in force
  /// across Reset and engine changes.
  void SetExcludedCollisionEvents(bool on);

  /// One simulation step of /Simulation/TimeStepSize seconds (IterationsPerStep physics steps of that size
  /// each, as the original). Does nothing once the status is not kOk.
  SimulationStatus Step();

  /// Simulated seconds one Step() advances: TimeStepSize × IterationsPerStep. Throws InputError naming the path
  /// when a run-time parameter is out of range.
  double StepDuration();

  VariableRepository& repository() { return repository_; }
  const VariableRepository& repository() const { return repository_; }
  EventManager& events() { return events_; }
  const WorldModel& model() const { return *model_; }
  /// The compiled model, to Attach() further simulations to (a job's parameter sets share one).
  std::shared_ptr<const WorldModel> shared_model() const { return model_; }
  bool built() const { return model_ != nullptr; }
  const physics::PhysicsWorld& physics() const { return *world_; }
  /// The engine the world runs on, "ODE" or "MuJoCo" (/Simulation/Engine when the world was made).
  const std::string& engine() const { return world_engine_; }
  /// The robots, in environment order.
  int agent_count() const { return static_cast<int>(agents_.size()); }
  aseries::ASeriesAgent& agent(int index) { return *agents_[index]; }
  /// Index of the agent called `name`, or -1.
  int FindAgent(std::string_view name) const;

  double time() const { return time_; }          ///< simulated seconds since the last reset
  /// The seed of the last Reset (/Simulation/Seed): what the run's own random streams derive from.
  std::uint64_t seed() const;
  std::int64_t steps() const { return steps_; }  ///< simulation steps since the last reset
  SimulationStatus status() const { return status_; }
  const std::string& message() const { return message_; }  ///< why the status is not kOk

 private:
  void RegisterSimulationValues();
  void RegisterMujocoValues();
  void MakeWorld();
  void BindModel();
  void WatchStructure(const EnvironmentDescription& environment);
  void ApplyStructureChanges();
  void ReadParameters();
  void ReadMujocoSettings();
  void CheckEngineOnlyValues() const;
  void PhysicsStage();
  void PublishBodiesStage();
  void CollisionEventsStage();
  void TurnHinge(const PosingJoint& hinge, double angle_rad);

  VariableRepository repository_;
  EventManager events_;
  EnvironmentDescription environment_;  // loaded, not yet built
  std::shared_ptr<const WorldModel> model_;
  std::unique_ptr<physics::PhysicsWorld> world_;
  std::string world_engine_;  ///< the engine world_ runs on: /Simulation/Engine when it was made
  bool excluded_collision_events_ = true;  ///< SetExcludedCollisionEvents
  /// A value only one engine reads (/Simulation/ODE/ERP, /Simulation/MuJoCo/Solver, ...): moved from its default
  /// while the other engine runs, it is refused rather than silently ignored.
  struct EngineOnlyValue {
    std::string path;
    std::string engine;        ///< the engine that reads it
    std::string default_text;  ///< its registered default, as Value::ToString prints it
  };
  std::vector<EngineOnlyValue> engine_only_values_;
  std::vector<std::unique_ptr<aseries::ASeriesAgent>> agents_;  // their observers point into them: not movable
  physics::PhysicsParameters parameters_;
  bool parameters_changed_ = true;  // set by observers of the /Simulation/... values
  /// Set by observers of the structure values: one may differ from the compiled model (checked at Reset).
  bool structure_changed_ = false;
  /// True while the simulation itself writes the bodies' published pose, which is no new start pose.
  bool publishing_pose_ = false;
  /// An object's start pose written from outside since the last compile: path → value text.
  std::unordered_map<std::string, std::string> written_start_pose_;

  double time_ = 0.0;
  std::int64_t steps_ = 0;
  double time_base_ = 0.0;        // time when the step size last changed
  std::int64_t steps_base_ = 0;  // steps_ then
  SimulationStatus status_ = SimulationStatus::kOk;
  std::string message_;

  // Values and events the step touches, looked up once (no lookups or allocation inside the step loop).
  Value* time_step_ = nullptr;
  Value* iterations_ = nullptr;
  Value* current_time_ = nullptr;
  Value* current_step_ = nullptr;
  struct BodyBinding {
    Value* position = nullptr;
    Value* orientation = nullptr;
    Value* quaternion = nullptr;
    int collision_event = -1;
  };
  std::vector<BodyBinding> bodies_;
  int step_event_ = -1;
  int reset_event_ = -1;
};

}  // namespace orcs::scene
