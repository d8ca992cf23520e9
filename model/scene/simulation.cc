#include "model/scene/simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/demand.h"
#include "model/core/error.h"
#include "model/core/rotation.h"
#include "model/core/text.h"
#include "model/physics/mujoco/mujoco_world.h"
#include "model/physics/ode/ode_world.h"
#include "model/scene/engine_names.h"

namespace orcs::scene {
namespace {

using physics::PhysicsParameters;

// Repository values that map one-to-one onto a double of PhysicsParameters (spec/aseries.md §8).
struct DoubleParameter {
  const char* path;
  double PhysicsParameters::*member;
};
constexpr DoubleParameter kDoubleParameters[] = {
    {"/Simulation/ODE/ERP", &PhysicsParameters::erp},
    {"/Simulation/ODE/ConstraintForceMixing", &PhysicsParameters::cfm},
    {"/Simulation/ODE/ContactSurfaceLayer", &PhysicsParameters::contact_surface_layer},
    {"/Simulation/ODE/ContactMaxCorrectingVelocity", &PhysicsParameters::contact_max_correcting_velocity},
    {"/Simulation/ODE/SoftERP", &PhysicsParameters::soft_erp},
    {"/Simulation/ODE/SoftCFM", &PhysicsParameters::soft_cfm},
    {"/Simulation/ODE/ContactSlip", &PhysicsParameters::contact_slip},
    {"/Simulation/ODE/MinimumBouncingVelocity", &PhysicsParameters::min_bouncing_velocity},
    {"/Simulation/ODE/FrictionScaling", &PhysicsParameters::friction_scaling},
    {"/Simulation/ODE/StaticFrictionSpeed", &PhysicsParameters::static_friction_speed},
};

// The two user materials' values (the original's spelling "StateFriction" kept for old value files).
struct CustomMaterialParameter {
  const char* path;
  physics::CustomMaterial PhysicsParameters::*material;
  double physics::CustomMaterial::*member;
};
constexpr CustomMaterialParameter kCustomMaterialParameters[] = {
    {"/MaterialProperties/Custom1/StateFriction", &PhysicsParameters::custom1, &physics::CustomMaterial::static_friction},
    {"/MaterialProperties/Custom1/DynamicFriction", &PhysicsParameters::custom1, &physics::CustomMaterial::dynamic_friction},
    {"/MaterialProperties/Custom1/Restitution", &PhysicsParameters::custom1, &physics::CustomMaterial::restitution},
    {"/MaterialProperties/Custom2/StateFriction", &PhysicsParameters::custom2, &physics::CustomMaterial::static_friction},
    {"/MaterialProperties/Custom2/DynamicFriction", &PhysicsParameters::custom2, &physics::CustomMaterial::dynamic_friction},
    {"/MaterialProperties/Custom2/Restitution", &PhysicsParameters::custom2, &physics::CustomMaterial::restitution},
};

constexpr const char* kEngine = "/Simulation/Engine";
constexpr const char* kTimeStep = "/Simulation/TimeStepSize";
constexpr const char* kIterations = "/Simulation/IterationsPerStep";
constexpr const char* kGravitation = "/Simulation/Gravitation";
constexpr const char* kUseQuickStep = "/Simulation/ODE/UseQuickStep";
constexpr const char* kQuickStepIterations = "/Simulation/ODE/QuickStepIterations";
constexpr const char* kMaxContactPoints = "/Simulation/ODE/MaxContactPoints";
constexpr const char* kMujocoSolver = "/Simulation/MuJoCo/Solver";
constexpr const char* kMujocoIterations = "/Simulation/MuJoCo/Iterations";
constexpr const char* kMujocoTolerance = "/Simulation/MuJoCo/Tolerance";
constexpr const char* kMujocoIntegrator = "/Simulation/MuJoCo/Integrator";
constexpr const char* kMujocoCone = "/Simulation/MuJoCo/Cone";
constexpr const char* kMujocoTimeConstant = "/Simulation/MuJoCo/ContactTimeConstant";
constexpr const char* kMujocoDampingRatio = "/Simulation/MuJoCo/ContactDampingRatio";
// What only ODE reads. FrictionScaling and StaticFrictionSpeed keep the original's /Simulation/ODE/ path but
// are the material model's, read by both engines.
constexpr const char* kOdeOnlyValues[] = {
    kUseQuickStep, kQuickStepIterations, kMaxContactPoints, "/Simulation/ODE/ERP",
    "/Simulation/ODE/ConstraintForceMixing", "/Simulation/ODE/ContactSurfaceLayer",
    "/Simulation/ODE/ContactMaxCorrectingVelocity", "/Simulation/ODE/SoftERP", "/Simulation/ODE/SoftCFM",
    "/Simulation/ODE/ContactSlip", "/Simulation/ODE/MinimumBouncingVelocity"};
constexpr const char* kMujocoOnlyValues[] = {kMujocoSolver, kMujocoIterations,   kMujocoTolerance,   kMujocoIntegrator,
                                             kMujocoCone,   kMujocoTimeConstant, kMujocoDampingRatio};
constexpr double kMaxIterationsPerStep = 1000;
constexpr double kMaxQuickStepIterations = 100000;
constexpr double kMaxContactPointsValue = 1e6;  // used up to PhysicsParameters::kMaxContactPoints

}  // namespace

std::string_view SimulationStatusName(SimulationStatus status) {
  switch (status) {
    case SimulationStatus::kOk: return "ok";
    case SimulationStatus::kUnstable: return "unstable physics";
    case SimulationStatus::kEngineError: return "physics engine error";
  }
  return "?";
}

Simulation::Simulation() { RegisterSimulationValues(); }
Simulation::~Simulation() = default;

void Simulation::RegisterSimulationValues() {
  const PhysicsParameters defaults;
  const auto watch = [this](Value& value) { value.AddObserver([this](const Value&) { parameters_changed_ = true; }); };
  // The ranges (docs/orcs-sim.md): a step of 1e-300 s or 1e300 s is no simulation, and a value written from
  // outside (a value file, a job, OSP) is refused where it is written, naming the path, not at the next step.
  time_step_ = &repository_.Add(kTimeStep, 0.01).SetRange(kMinTimeStep, kMaxTimeStep);
  iterations_ = &repository_.Add(kIterations, 1).SetRange(1, kMaxIterationsPerStep);
  // The physics engine (docs/model.md): a world is made on it at Build/Attach and again at a Reset after it changed.
  watch(repository_.Add(kEngine, EngineNames().front()).SetChoices(EngineNames()));
  watch(*time_step_);
  watch(*iterations_);
  watch(repository_.Add(kGravitation, -defaults.gravity.y()));
  watch(repository_.Add(kUseQuickStep, defaults.solver == physics::Solver::kQuickStep));
  watch(repository_.Add(kQuickStepIterations, defaults.quickstep_iterations).SetRange(1, kMaxQuickStepIterations));
  watch(repository_.Add(kMaxContactPoints, defaults.max_contact_points).SetRange(1, kMaxContactPointsValue));
  for (const DoubleParameter& p : kDoubleParameters) watch(repository_.Add(p.path, defaults.*p.member));
  for (const CustomMaterialParameter& p : kCustomMaterialParameters) {
    watch(repository_.Add(p.path, defaults.*p.material.*p.member));
  }
  RegisterMujocoValues();
  for (const char* path : kOdeOnlyValues) engine_only_values_.push_back({path, "ODE", repository_.Get(path).ToString()});
  for (const char* path : kMujocoOnlyValues) {
    engine_only_values_.push_back({path, "MuJoCo", repository_.Get(path).ToString()});
  }
  current_time_ = &repository_.Add("/Simulation/CurrentSimulationTime", 0.0);
  current_step_ = &repository_.Add("/Simulation/CurrentStep", 0);
  repository_.Add("/Simulation/Seed", 0);
  step_event_ = events_.Register("/Simulation/Step");
  reset_event_ = events_.Register("/Simulation/Reset");
}

// The MuJoCo engine's solver (docs/orcs-sim.md): read at every step like the rest, no recompiling needed.
void Simulation::RegisterMujocoValues() {
  const physics::MujocoSettings defaults;
  const auto watch = [this](Value& value) { value.AddObserver([this](const Value&) { parameters_changed_ = true; }); };
  // CG and PGS are MuJoCo solvers too, but the motor rows fail on them (docs/model.md): not offered.
  watch(repository_.Add(kMujocoSolver, std::string("Newton")).SetChoices({"Newton"}));
  watch(repository_.Add(kMujocoIterations, defaults.iterations).SetRange(1, kMaxQuickStepIterations));
  watch(repository_.Add(kMujocoTolerance, defaults.tolerance).SetRange(0, 1));
  watch(repository_.Add(kMujocoIntegrator, std::string("Euler")).SetChoices({"Euler", "Implicit"}));
  watch(repository_.Add(kMujocoCone, std::string("Pyramidal")).SetChoices({"Pyramidal", "Elliptic"}));
  watch(repository_.Add(kMujocoTimeConstant, defaults.contact_time_constant).SetRange(1e-6, 10));
  watch(repository_.Add(kMujocoDampingRatio, defaults.contact_damping_ratio).SetRange(1e-3, 100));
}

void Simulation::LoadEnvironment(const EnvironmentDescription& environment) {
  ORCS_DEMAND_MSG(!built(), "LoadEnvironment() after Build()");
  WorldModel::RegisterObjectValues(environment, repository_);
  for (const AgentDescription& agent : environment.agents) {  // for -ival
    aseries::ASeriesAgent::AddAgentParameters(repository_, agent.name, *WorldModel::MorphologyOf(agent));
  }
  environment_ = environment;
  WatchStructure(environment);
}

void Simulation::Build() {
  ORCS_DEMAND_MSG(!built(), "Build() twice");
  model_ = WorldModel::Compile(environment_, repository_);
  BindModel();
}

void Simulation::Attach(std::shared_ptr<const WorldModel> model) {
  ORCS_DEMAND_MSG(!built(), "Attach() after Build()");
  WorldModel::RegisterObjectValues(model->environment(), repository_);
  // The repository says what the model was compiled from, so that a reset does not compile it back to the
  // environment's own values.
  for (const WorldModel::StructureValue& value : model->structure()) repository_.Set(value.path, value.text);
  WatchStructure(model->environment());
  model_ = std::move(model);
  BindModel();
}

// Every structure value's write marks the world for a check at the next reset. The objects' poses are also what
// the physics publishes: only a write from outside the step is a new start pose, kept until then.
void Simulation::WatchStructure(const EnvironmentDescription& environment) {
  for (const WorldModel::StructureValue& structure : WorldModel::StructurePaths(environment)) {
    const std::string path = structure.path;
    const bool pose = structure.pose;
    repository_.Get(path).AddObserver([this, path, pose](const Value& value) {
      if (publishing_pose_) return;
      structure_changed_ = true;
      if (pose) written_start_pose_[path] = value.ToString();
    });
  }
}

// At a reset: compiles the world again when a structure value differs from what it was compiled from. The
// objects' poses go back to their start (the compiled one, or one written from outside since) before.
void Simulation::ApplyStructureChanges() {
  std::vector<std::pair<std::string, std::string>> start_pose;
  bool changed = false;
  for (const WorldModel::StructureValue& compiled : model_->structure()) {
    std::string now;
    if (compiled.pose) {
      const auto written = written_start_pose_.find(compiled.path);
      now = written == written_start_pose_.end() ? compiled.text : written->second;
      start_pose.emplace_back(compiled.path, now);
    } else {
      now = repository_.Get(compiled.path).ToString();
    }
    changed = changed || now != compiled.text;
  }
  if (changed) {
    publishing_pose_ = true;  // the start pose, not a write from outside
    for (const auto& [path, text] : start_pose) repository_.Set(path, text);
    publishing_pose_ = false;
    // A value that cannot be compiled throws here and leaves everything as it was: the next reset says so again.
    std::shared_ptr<const WorldModel> recompiled = WorldModel::Compile(model_->environment(), repository_);
    // Values change numbers, never the bodies and joints: the agents' indices into the world stay valid.
    ORCS_DEMAND_MSG(recompiled->physics()->body_count() == model_->physics()->body_count() &&
                        recompiled->physics()->joint_count() == model_->physics()->joint_count(),
                    "a structure value changed the world's bodies or joints");
    model_ = std::move(recompiled);
    for (std::size_t a = 0; a < agents_.size(); ++a) {
      agents_[a]->UpdateGeometry(model_->morphology(static_cast<int>(a)), model_->agents()[a]);
    }
    MakeWorld();
  }
  written_start_pose_.clear();
  structure_changed_ = false;
}

void Simulation::KeepPoseAsStart(const std::string& name) {
  ORCS_DEMAND_MSG(built(), "KeepPoseAsStart() before Build()");
  const std::vector<ObjectDescription>& objects = model_->environment().objects;
  if (std::none_of(objects.begin(), objects.end(), [&](const ObjectDescription& o) { return o.name == name; })) {
    throw InputError(name, 0, "no object of the environment has this name: only an object's pose can be kept as "
                              "its start (a robot starts where its agent is placed)");
  }
  for (const char* leaf : {"Position", "Orientation"}) {
    const std::string path = "/Sim/" + name + "/" + leaf;
    written_start_pose_[path] = repository_.Get(path).ToString();
  }
  structure_changed_ = true;
}

void Simulation::MakeWorld() {
  world_engine_ = repository_.Get(kEngine).as_string();
  world_ = world_engine_ == "MuJoCo" ? physics::MakeMujocoWorld(model_->physics())
                                     : physics::MakeOdeWorld(model_->physics());
  world_->SetReportExcludedContacts(excluded_collision_events_);
}

void Simulation::SetExcludedCollisionEvents(bool on) {
  excluded_collision_events_ = on;
  if (world_ != nullptr) world_->SetReportExcludedContacts(on);
}

void Simulation::BindModel() {
  MakeWorld();
  const physics::PhysicsModel& physics = *model_->physics();
  agents_.clear();
  for (int a = 0; a < static_cast<int>(model_->agents().size()); ++a) {
    agents_.push_back(
        std::make_unique<aseries::ASeriesAgent>(model_->morphology(a), model_->agents()[a], a, repository_));
  }
  bodies_.assign(physics.body_count(), {});
  for (int body = 0; body < physics.body_count(); ++body) {
    const std::string& name = model_->body_name(body);
    BodyBinding& binding = bodies_[body];
    if (physics.body(body).dynamic) {
      binding.position = repository_.Find("/Sim/" + name + "/Position");
      binding.orientation = repository_.Find("/Sim/" + name + "/Orientation");
      binding.quaternion = repository_.Find("/Sim/" + name + "/OrientationQuaternion");
    }
    binding.collision_event = events_.Register("/Sim/" + name + "/Collision");
  }
  Reset(static_cast<std::uint64_t>(repository_.Get("/Simulation/Seed").as_int()));
}

void Simulation::ReadParameters() {
  const auto positive = [this](const char* path) {
    const Value& value = repository_.Get(path);
    const double number = value.type() == ValueType::kInt ? static_cast<double>(value.as_int()) : value.as_double();
    if (!(number > 0) || std::isinf(number)) {
      throw InputError(path, 0, "expected a positive number, found " + value.ToString());
    }
    return number;
  };
  positive(kTimeStep);
  positive(kIterations);
  time_base_ = time_;  // the step size may have changed: count time from here
  steps_base_ = steps_;
  if (repository_.Get(kEngine).as_string() != world_engine_) {
    throw InputError(kEngine, 0, "the engine changes only at a reset: set it before the run starts (a value file, "
                                 "the scenario's values or the job's overrides)");
  }
  CheckEngineOnlyValues();
  parameters_.gravity = {0.0, -repository_.Get(kGravitation).as_double(), 0.0};
  parameters_.solver =
      repository_.Get(kUseQuickStep).as_bool() ? physics::Solver::kQuickStep : physics::Solver::kWorldStep;
  parameters_.quickstep_iterations = static_cast<int>(positive(kQuickStepIterations));
  parameters_.max_contact_points = static_cast<int>(
      std::min<double>(positive(kMaxContactPoints), PhysicsParameters::kMaxContactPoints));
  for (const DoubleParameter& p : kDoubleParameters) parameters_.*p.member = repository_.Get(p.path).as_double();
  for (const CustomMaterialParameter& p : kCustomMaterialParameters) {
    parameters_.*p.material.*p.member = repository_.Get(p.path).as_double();
  }
  ReadMujocoSettings();
  parameters_changed_ = false;
}

void Simulation::ReadMujocoSettings() {
  physics::MujocoSettings& settings = parameters_.mujoco;
  const std::string solver = repository_.Get(kMujocoSolver).as_string();
  settings.solver = solver == "PGS"  ? physics::MujocoSolver::kPGS
                    : solver == "CG" ? physics::MujocoSolver::kCG
                                     : physics::MujocoSolver::kNewton;
  settings.iterations = static_cast<int>(repository_.Get(kMujocoIterations).as_int());
  settings.tolerance = repository_.Get(kMujocoTolerance).as_double();
  settings.implicit_integrator = repository_.Get(kMujocoIntegrator).as_string() == "Implicit";
  settings.elliptic_cone = repository_.Get(kMujocoCone).as_string() == "Elliptic";
  settings.contact_time_constant = repository_.Get(kMujocoTimeConstant).as_double();
  settings.contact_damping_ratio = repository_.Get(kMujocoDampingRatio).as_double();
}

void Simulation::CheckEngineOnlyValues() const {
  for (const EngineOnlyValue& only : engine_only_values_) {
    if (only.engine == world_engine_ || repository_.Get(only.path).ToString() == only.default_text) continue;
    throw InputError(only.path, 0, "applies to the " + only.engine + " engine only, and /Simulation/Engine is " +
                                       world_engine_ + ": set /Simulation/Engine=" + only.engine + " or leave " +
                                       only.path + " at its default " + only.default_text);
  }
}

void Simulation::Reset(std::uint64_t seed) {
  ORCS_DEMAND_MSG(built(), "Reset() before Build()");
  if (structure_changed_) ApplyStructureChanges();
  if (repository_.Get(kEngine).as_string() != world_engine_) MakeWorld();
  world_->Reset();
  for (auto& agent : agents_) agent->Reset(*world_, seed);
  time_ = 0.0;
  steps_ = 0;
  time_base_ = 0.0;
  steps_base_ = 0;
  status_ = SimulationStatus::kOk;
  message_.clear();
  repository_.Get("/Simulation/Seed").Set(static_cast<std::int64_t>(seed));
  current_time_->Set(0.0);
  current_step_->Set(std::int64_t{0});
  events_.BeginStep();
  PublishBodiesStage();
  events_.Trigger(reset_event_);
}

SimulationStatus Simulation::Step() {
  ORCS_DEMAND_MSG(built(), "Step() before Build()");
  if (status_ != SimulationStatus::kOk) return status_;
  events_.BeginStep();
  if (parameters_changed_) ReadParameters();  // may throw InputError for values set since the last step
  const std::int64_t iterations = iterations_->as_int();
  const double dt = time_step_->as_double();
  for (std::int64_t i = 0; i < iterations && status_ == SimulationStatus::kOk; ++i) {
    for (auto& agent : agents_) agent->MotorStage(*world_, dt);
    PhysicsStage();  // collide → integrate → clear contacts → instability check
    if (status_ != SimulationStatus::kOk) break;
    CollisionEventsStage();
    for (auto& agent : agents_) agent->SensorStage(*world_, dt);
  }
  if (status_ != SimulationStatus::kOk) return status_;
  PublishBodiesStage();
  ++steps_;
  // Time as base + n·dt rather than a running sum, so that t = 0.37 prints as 0.37, not 0.37000000000000016.
  time_ = time_base_ + static_cast<double>(steps_ - steps_base_) * time_step_->as_double() *
                           static_cast<double>(iterations);
  current_time_->Set(time_);
  current_step_->Set(steps_);
  events_.Trigger(step_event_);
  return status_;
}

double Simulation::StepDuration() {
  if (parameters_changed_) ReadParameters();
  return time_step_->as_double() * static_cast<double>(iterations_->as_int());
}

void Simulation::PhysicsStage() {
  switch (world_->Step(time_step_->as_double(), parameters_)) {
    case physics::StepStatus::kOk: return;
    case physics::StepStatus::kUnstable:
      status_ = SimulationStatus::kUnstable;
      message_ = "unstable physics at t=" + text::FormatDouble(time_) + " s (non-finite or exploding state)";
      return;
    case physics::StepStatus::kEngineError:
      status_ = SimulationStatus::kEngineError;
      message_ = "physics engine error at t=" + text::FormatDouble(time_) + " s: " + world_->last_error();
      return;
  }
}

void Simulation::MoveAgent(int index, const Eigen::Vector3d& offset, double yaw_degrees) {
  ORCS_DEMAND_MSG(built() && steps_ == 0, "MoveAgent() right after Reset()");
  const Eigen::Vector3d pivot = model_->environment().agents[index].position;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(DegreesToRadians(yaw_degrees), Eigen::Vector3d::UnitY()));
  for (int body : model_->agents()[index].bodies) {
    physics::BodyState state = world_->body_state(body);
    state.position = pivot + offset + turn * (state.position - pivot);
    state.orientation = turn * state.orientation;
    state.linear_velocity = turn * state.linear_velocity;
    state.angular_velocity = turn * state.angular_velocity;
    world_->SetBodyState(body, state);
  }
  agents_[index]->Reset(*world_, seed());
  PublishBodiesStage();
}

void Simulation::SetAgentJointAngles(int index, const std::vector<double>& degrees) {
  ORCS_DEMAND_MSG(built() && steps_ == 0, "SetAgentJointAngles() right after Reset()");
  const aseries::ASeriesLayout& layout = model_->agents()[index];
  const aseries::ASeriesMorphology& morphology = model_->morphology(index);
  ORCS_DEMAND_MSG(degrees.size() == layout.motors.size(), "one angle per motor");
  const physics::PhysicsModel& physics = *model_->physics();
  for (const PosingJoint& hinge : PosingOrder(physics, layout, PosingRoot(physics, layout, morphology))) {
    const double angle = degrees[hinge.motor];
    ORCS_DEMAND_MSG(angle >= morphology.motors[hinge.motor].min_degrees && angle <= morphology.motors[hinge.motor].max_degrees, "within the motor's range");
    TurnHinge(hinge, DegreesToRadians(angle));
  }
  agents_[index]->Reset(*world_, seed());
  PublishBodiesStage();
}

// Turns the far side of `hinge` rigidly about the hinge's line until the hinge reads `angle_rad`.
void Simulation::TurnHinge(const PosingJoint& hinge, double angle_rad) {
  const double change = angle_rad - world_->joint_angle(hinge.joint);
  if (change == 0.0) return;
  const physics::BodyState proximal =
      hinge.proximal_body < 0 ? physics::BodyState{} : world_->body_state(hinge.proximal_body);
  const HingeLine line = HingeLineNow(*model_->physics(), hinge, proximal);
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(hinge.sign * change, line.axis));
  for (int body : hinge.distal_bodies) {
    physics::BodyState state = world_->body_state(body);
    state.position = line.anchor + turn * (state.position - line.anchor);
    state.orientation = (turn * state.orientation).normalized();
    state.linear_velocity = turn * state.linear_velocity;  // zero right after a reset, and so it stays
    state.angular_velocity = turn * state.angular_velocity;
    world_->SetBodyState(body, state);
  }
}

std::uint64_t Simulation::seed() const {
  return static_cast<std::uint64_t>(repository_.Get("/Simulation/Seed").as_int());
}

void Simulation::PublishBodiesStage() {
  publishing_pose_ = true;  // the moving pose, not a new start pose
  for (size_t body = 0; body < bodies_.size(); ++body) {
    const BodyBinding& binding = bodies_[body];
    if (binding.position == nullptr) continue;
    const physics::BodyState state = world_->body_state(static_cast<int>(body));
    binding.position->Set(state.position);
    binding.quaternion->Set(state.orientation);
    binding.orientation->Set(EulerDegreesFromQuaternion(state.orientation));
  }
  publishing_pose_ = false;
}

void Simulation::CollisionEventsStage() {
  for (const physics::Contact& contact : world_->contacts()) {
    events_.Trigger(bodies_[contact.body1].collision_event);
    events_.Trigger(bodies_[contact.body2].collision_event);
  }
}

int Simulation::FindAgent(std::string_view name) const {
  for (int a = 0; a < agent_count(); ++a) {
    if (agents_[a]->name() == name) return a;
  }
  return -1;
}

}  // namespace orcs::scene
