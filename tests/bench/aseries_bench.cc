// Steps per second of the A-Series standing (scene::Simulation: Dynamixel motor model, angle sensors,
// accelerometers, repository values, events) against the same bodies and joints stepped with raw ODE calls and
// no motor or sensor model; and the speed of ODE's iterative solver (dWorldQuickStep) against the exact one.
// Items/s = simulation steps per second; realtime_factor = simulated seconds per second. Target: the motor and
// sensor models together cost at most 15 % over raw ODE (issue 3). The overhead is printed after the run.
//
// The raw side (RawOdeASeries) is built from the compiled physics::PhysicsModel of the same world: the same
// bodies, masses, geoms (offsets, the penetrable pelvis box), hinges with their stops, fixed joints, world and
// contact parameters, material table, static/dynamic friction rule and collision exclusions, made in the same
// order. What it lacks is the motor model: each hinge is held by its own ODE motor (velocity 0, FMax = the torque
// limit the motor model applies by default, 0.615 N·m) so that the robot stands and the contact load is the
// same; there is no angular motor, no friction brake, no PID, no sensor and no repository.
// BM_ASeriesRawOdeMotorJoints adds back only the motor model's ODE joints, held at constant settings: an angular
// motor and a hinge friction brake per hinge, two rows on one axis. Stepped as two rows they make ODE's pivoting
// solver shuttle between them and cost more than the whole rest of the step; OdeWorld therefore solves each pair as
// one row whenever it can prove which of the two is at its limit (docs/model.md, "Motor and brake rows"). This
// variant shows what that saves. Before timing, the program checks that the simulation and the raw robots stand
// (head height after 10 s) with the same contact load, and reports whether QuickStep keeps the robot up.
//
// Episodes are 10 s simulated (1000 steps of 10 ms); both sides reset between episodes outside the timing by
// rebuilding their ODE world, which is what Simulation::Reset does.
//
//   aseries_bench --benchmark_repetitions=5 --benchmark_min_time=2 --benchmark_report_aggregates_only=true
//                 --benchmark_enable_random_interleaving=true
#include <benchmark/benchmark.h>
#include <ode/ode.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "model/aseries/dynamixel_motor.h"
#include "model/aseries/value_range.h"
#include "model/physics/material_table.h"
#include "model/physics/ode/ode_joints.h"
#include "model/physics/physics_model.h"
#include "model/physics/physics_parameters.h"
#include "model/scene/simulation.h"
#include "tests/bench/rate_reporter.h"

namespace orcs::scene {
namespace {

using physics::PhysicsModel;
using physics::PhysicsParameters;

constexpr double kDt = 0.01;         // s, the default /Simulation/TimeStepSize
constexpr int kEpisodeSteps = 1000;  // 10 s simulated, then reset
constexpr const char* kHeadPath = "/Sim/Humanoid/Middle/Head/Position";
constexpr const char* kHeadBody = "Humanoid/Middle/Head";
constexpr int kQuickStepIterations[] = {10, 20, 50, 100, 200};

// The torque limit the motor model gives every motor by default: FMaxFactor × DesiredTorque (spec §6c).
double DefaultHoldTorque() {
  return aseries::TorqueLimit(aseries::DynamixelParameters{}, aseries::kDefaultDesiredTorqueRaw);
}

// One A-Series named Humanoid on the floor, default parameters: what orcs-sim runs without arguments.
std::unique_ptr<Simulation> MakeStandingSimulation() {
  auto simulation = std::make_unique<Simulation>();
  EnvironmentDescription environment;
  environment.source = "(default: one A-Series named Humanoid on the floor)";
  environment.agents.push_back(AgentDescription{});
  simulation->LoadEnvironment(environment);
  simulation->Build();
  return simulation;
}

// The robot of a compiled PhysicsModel in raw ODE, written as a user without the motor model would: every
// constant resolved once, one callback, no bookkeeping beyond counting contact joints.
class RawOdeASeries {
 public:
  enum class Hold {
    kHingeMotor,   // each hinge's own motor: velocity 0, FMax = hold torque
    kMotorJoints,  // the motor model's ODE joints: an angular motor (velocity 0, FMax = hold torque) created
                   // before each hinge, and the hinge's motor as a friction brake (velocity 0, FMax = 0.001 N·m,
                   // the static friction the model applies at rest)
  };

  RawOdeASeries(std::shared_ptr<const PhysicsModel> model, Hold hold) : model_(std::move(model)), hold_(hold) {
    const PhysicsModel& m = *model_;
    const physics::BodyFrictionParameters no_fallback;
    materials_.resize(static_cast<size_t>(m.geom_count() * m.geom_count()));
    for (int g1 = 0; g1 < m.geom_count(); ++g1) {
      for (int g2 = 0; g2 < m.geom_count(); ++g2) {
        const int b1 = m.geom(g1).body;
        const int b2 = m.geom(g2).body;
        const physics::BodyFrictionParameters f1{m.body(b1).static_friction, m.body(b1).dynamic_friction,
                                                 m.body(b1).elasticity};
        const physics::BodyFrictionParameters f2{m.body(b2).static_friction, m.body(b2).dynamic_friction,
                                                 m.body(b2).elasticity};
        PairInfo& pair = materials_[static_cast<size_t>(g1 * m.geom_count() + g2)];
        pair.material = physics::MaterialTable::Lookup(m.geom(g1).material, m.geom(g2).material, f1, f2,
                                                       parameters_.custom1, parameters_.custom2);
        pair.excluded = m.contact_excluded(b1, b2);
      }
    }
    Build();
  }
  ~RawOdeASeries() { Destroy(); }
  RawOdeASeries(const RawOdeASeries&) = delete;
  RawOdeASeries& operator=(const RawOdeASeries&) = delete;

  void Reset() {
    Destroy();
    Build();
  }

  bool Step() {
    dSpaceCollide(space_, this, &RawOdeASeries::NearCallback);
    const int ok = dWorldStep(world_, kDt);
    dJointGroupEmpty(contacts_);
    return ok != 0;
  }

  const dReal* position(int body) const { return dBodyGetPosition(bodies_[body]); }
  std::int64_t contact_joints() const { return contact_joints_; }

 private:
  struct PairInfo {
    physics::ContactMaterial material;
    bool excluded = false;
  };

  static void* IndexToData(int index) { return reinterpret_cast<void*>(static_cast<std::intptr_t>(index)); }
  static int DataToIndex(void* data) { return static_cast<int>(reinterpret_cast<std::intptr_t>(data)); }
  static void NearCallback(void* data, dGeomID o1, dGeomID o2) {
    static_cast<RawOdeASeries*>(data)->Collide(o1, o2);
  }

  void Build() {
    const PhysicsModel& m = *model_;
    const PhysicsParameters& p = parameters_;
    world_ = dWorldCreate();
    dWorldSetERP(world_, p.erp);  // before the joints: their stops take the world's ERP/CFM at creation
    dWorldSetCFM(world_, p.cfm);
    dWorldSetGravity(world_, p.gravity.x(), p.gravity.y(), p.gravity.z());
    dWorldSetContactSurfaceLayer(world_, p.contact_surface_layer);
    dWorldSetContactMaxCorrectingVel(world_, p.contact_max_correcting_velocity);
    space_ = dSimpleSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    bodies_.assign(m.body_count(), nullptr);
    for (int b = 0; b < m.body_count(); ++b) BuildBody(b);
    for (int j = 0; j < m.joint_count(); ++j) BuildJoint(j);
  }

  void Destroy() {
    if (contacts_ != nullptr) dJointGroupDestroy(contacts_);
    if (space_ != nullptr) dSpaceDestroy(space_);
    if (world_ != nullptr) dWorldDestroy(world_);
    contacts_ = nullptr;
    space_ = nullptr;
    world_ = nullptr;
  }

  void BuildBody(int b) {
    const physics::BodyDescription& body = model_->body(b);
    dBodyID id = nullptr;
    if (body.dynamic) {
      id = dBodyCreate(world_);
      dBodySetPosition(id, body.position.x(), body.position.y(), body.position.z());
      const dQuaternion q = {body.orientation.w(), body.orientation.x(), body.orientation.y(), body.orientation.z()};
      dBodySetQuaternion(id, q);
      // The original's mass rule: a uniform box of the main geom carrying the body's total mass, at the origin.
      // (Every A-Series main geom is an unrotated box.)
      const physics::GeomDescription& main = body.geoms[0];
      dMass mass;
      dMassSetZero(&mass);
      dMassSetBoxTotal(&mass, model_->total_mass(b), main.size.x(), main.size.y(), main.size.z());
      dBodySetMass(id, &mass);
    }
    bodies_[b] = id;
    const int first = model_->first_geom(b);
    for (int g = 0; g < static_cast<int>(body.geoms.size()); ++g) {
      const physics::GeomDescription& geom = body.geoms[g];
      dGeomID gid = nullptr;
      if (geom.shape == physics::Shape::kPlane) {
        gid = dCreatePlane(space_, 0, 1, 0, body.position.y());  // the floor: y = 0, normal up
      } else {
        gid = dCreateBox(space_, geom.size.x(), geom.size.y(), geom.size.z());
        dGeomSetBody(gid, id);
        if (!geom.offset.isZero(0.0)) dGeomSetOffsetPosition(gid, geom.offset.x(), geom.offset.y(), geom.offset.z());
        if (geom.rotation.w() != 1.0) {
          const dQuaternion q = {geom.rotation.w(), geom.rotation.x(), geom.rotation.y(), geom.rotation.z()};
          dGeomSetOffsetQuaternion(gid, q);
        }
      }
      if (!geom.collides) {  // the penetrable pelvis box
        dGeomSetCategoryBits(gid, 0);
        dGeomSetCollideBits(gid, 0);
      }
      dGeomSetData(gid, IndexToData(first + g));
    }
  }

  void BuildJoint(int j) {
    const physics::JointDescription& joint = model_->joint(j);
    dBodyID body1 = bodies_[model_->joint_body1(j)];
    dBodyID body2 = bodies_[model_->joint_body2(j)];  // every A-Series joint joins two robot bodies
    if (joint.type == physics::JointType::kFixed) {
      physics::CreateFixedJoint(world_, body1, body2);
      return;
    }
    const double hold_torque = DefaultHoldTorque();
    if (hold_ == Hold::kMotorJoints) {
      dJointID motor = dJointCreateAMotor(world_, nullptr);
      dJointAttach(motor, body1, body2);
      dJointSetAMotorMode(motor, dAMotorUser);
      dJointSetAMotorNumAxes(motor, 1);
      dJointSetAMotorAxis(motor, 0, 1, joint.axis.x(), joint.axis.y(), joint.axis.z());
      dJointSetAMotorParam(motor, dParamVel, 0.0);
      dJointSetAMotorParam(motor, dParamFMax, hold_torque);
      dJointSetAMotorParam(motor, dParamCFM, 1e-5);  // /ODEJoint/MotorCFM
    }
    dJointID hinge = physics::CreateHinge(world_, body1, body2, joint);
    dJointSetHingeParam(hinge, dParamFMax,
                        hold_ == Hold::kHingeMotor ? hold_torque : aseries::DynamixelParameters{}.static_friction);
  }

  void Collide(dGeomID o1, dGeomID o2) {
    const int g1 = DataToIndex(dGeomGetData(o1));
    const int g2 = DataToIndex(dGeomGetData(o2));
    const int b1 = model_->geom(g1).body;
    const int b2 = model_->geom(g2).body;
    if (b1 == b2) return;
    const int found = dCollide(o1, o2, parameters_.max_contact_points, points_.data(), sizeof(dContactGeom));
    const PairInfo& pair = materials_[static_cast<size_t>(g1 * model_->geom_count() + g2)];
    if (found == 0 || pair.excluded) return;
    dBodyID body1 = bodies_[b1];
    dBodyID body2 = bodies_[b2];
    const PhysicsParameters& p = parameters_;
    for (int i = 0; i < found; ++i) {
      const dContactGeom& point = points_[i];
      if (std::abs(point.depth) < p.min_contact_depth) continue;
      physics::CreateContactJoint(world_, contacts_, point, body1, body2, Friction(point, body1, body2, pair.material),
                                  pair.material, p);
      ++contact_joints_;
    }
  }

  // Static coefficient while the surfaces do not slide at the contact point, else the dynamic one (docs/model.md).
  double Friction(const dContactGeom& point, dBodyID b1, dBodyID b2, const physics::ContactMaterial& material) const {
    dVector3 v1 = {0.0, 0.0, 0.0, 0.0};
    dVector3 v2 = {0.0, 0.0, 0.0, 0.0};
    if (b1 != nullptr) dBodyGetPointVel(b1, point.pos[0], point.pos[1], point.pos[2], v1);
    if (b2 != nullptr) dBodyGetPointVel(b2, point.pos[0], point.pos[1], point.pos[2], v2);
    const double r[3] = {v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]};
    const double along = r[0] * point.normal[0] + r[1] * point.normal[1] + r[2] * point.normal[2];
    double slide2 = 0.0;
    for (int k = 0; k < 3; ++k) slide2 += (r[k] - along * point.normal[k]) * (r[k] - along * point.normal[k]);
    const double limit = parameters_.static_friction_speed;
    return slide2 < limit * limit ? material.static_friction
                                  : material.dynamic_friction * parameters_.friction_scaling;
  }

  std::shared_ptr<const PhysicsModel> model_;
  Hold hold_;
  const PhysicsParameters parameters_;  // the defaults: what the simulation reads from a fresh repository
  std::vector<PairInfo> materials_;     // per ordered geom pair: material and exclusion, resolved once
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::vector<dBodyID> bodies_;
  std::array<dContactGeom, PhysicsParameters::kMaxContactPoints> points_{};
  std::int64_t contact_joints_ = 0;
};

// Publishes what both sides report: steps/s (items) and simulated seconds per second.
void ReportSteps(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations());
  state.counters["realtime_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kDt, benchmark::Counter::kIsRate);
}

// Steps `simulation` in episodes of 10 s. A run that turns unstable is an error, unless `restart_unstable`: then
// it restarts (outside the timing) and is counted, since an iterative solver's speed is still worth knowing when
// it cannot hold the robot together.
void StepSimulation(benchmark::State& state, Simulation& simulation, bool restart_unstable) {
  std::int64_t unstable = 0;
  for (auto _ : state) {
    if (simulation.steps() == kEpisodeSteps || simulation.status() != SimulationStatus::kOk) {
      state.PauseTiming();
      simulation.Reset(0);
      state.ResumeTiming();
    }
    if (simulation.Step() != SimulationStatus::kOk) {
      if (restart_unstable) {
        ++unstable;
        continue;
      }
      state.SkipWithError(("step failed: " + simulation.message()).c_str());
      break;
    }
  }
  ReportSteps(state);
  if (restart_unstable) state.counters["unstable_runs"] = static_cast<double>(unstable);
}

void BM_ASeriesStanding(benchmark::State& state) {
  const std::unique_ptr<Simulation> simulation = MakeStandingSimulation();
  StepSimulation(state, *simulation, false);
}

void BM_ASeriesQuickStep(benchmark::State& state) {
  const std::unique_ptr<Simulation> simulation = MakeStandingSimulation();
  simulation->repository().Set("/Simulation/ODE/UseQuickStep", "T");
  simulation->repository().Set("/Simulation/ODE/QuickStepIterations", std::to_string(state.range(0)));
  StepSimulation(state, *simulation, true);
}

void StepRaw(benchmark::State& state, RawOdeASeries::Hold hold) {
  dInitODE2(0);
  dAllocateODEDataForThread(dAllocateMaskAll);
  RawOdeASeries robot(MakeStandingSimulation()->model().physics(), hold);
  int step = 0;
  for (auto _ : state) {
    if (step == kEpisodeSteps) {
      state.PauseTiming();
      robot.Reset();
      state.ResumeTiming();
      step = 0;
    }
    if (!robot.Step()) {
      state.SkipWithError("dWorldStep failed");
      break;
    }
    ++step;
  }
  ReportSteps(state);
}

void BM_ASeriesRawOde(benchmark::State& state) { StepRaw(state, RawOdeASeries::Hold::kHingeMotor); }
void BM_ASeriesRawOdeMotorJoints(benchmark::State& state) { StepRaw(state, RawOdeASeries::Hold::kMotorJoints); }

BENCHMARK(BM_ASeriesStanding)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ASeriesRawOde)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ASeriesRawOdeMotorJoints)->Unit(benchmark::kMicrosecond);
// 10–50 iterations as issue 3 asks; 100 and 200 because the robot does not stand below (see the check in main).
BENCHMARK(BM_ASeriesQuickStep)->Arg(10)->Arg(20)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);

// Both sides must simulate a standing robot with a similar contact load, or the comparison means nothing.
bool CheckStanding() {
  const std::unique_ptr<Simulation> simulation = MakeStandingSimulation();
  const int head = simulation->model().physics()->FindBody(kHeadBody);
  const double start = simulation->repository().Get(kHeadPath).as_vector3().y();
  std::int64_t simulation_contacts = 0;
  for (int i = 0; i < kEpisodeSteps; ++i) {
    if (simulation->Step() != SimulationStatus::kOk) {
      std::fprintf(stderr, "simulation failed: %s\n", simulation->message().c_str());
      return false;
    }
    for (const physics::Contact& contact : simulation->physics().contacts()) simulation_contacts += !contact.excluded;
  }
  const double simulation_drop = start - simulation->repository().Get(kHeadPath).as_vector3().y();

  dInitODE2(0);
  dAllocateODEDataForThread(dAllocateMaskAll);
  bool ok = std::abs(simulation_drop) < 0.01;
  std::fprintf(stderr, "standing 10 s: Simulation head drops %.2f mm, %.1f contact joints/step\n",
               simulation_drop * 1e3, static_cast<double>(simulation_contacts) / kEpisodeSteps);
  for (const auto hold : {RawOdeASeries::Hold::kHingeMotor, RawOdeASeries::Hold::kMotorJoints}) {
    RawOdeASeries raw(simulation->model().physics(), hold);
    for (int i = 0; i < kEpisodeSteps; ++i) {
      if (!raw.Step()) {
        std::fprintf(stderr, "raw ODE step failed\n");
        return false;
      }
    }
    const double raw_drop = start - raw.position(head)[1];
    ok = ok && std::abs(raw_drop) < 0.01;
    std::fprintf(stderr, "standing 10 s: raw ODE (%s) head drops %.2f mm, %.1f contact joints/step\n",
                 hold == RawOdeASeries::Hold::kHingeMotor ? "hinge motors" : "motor joints", raw_drop * 1e3,
                 static_cast<double>(raw.contact_joints()) / kEpisodeSteps);
  }
  if (!ok) std::fprintf(stderr, "a robot fell: the figures would compare different simulations\n");

  // Not a condition for the figures, but what they mean: whether the iterative solver keeps the robot standing.
  for (const int iterations : kQuickStepIterations) {
    const std::unique_ptr<Simulation> quick = MakeStandingSimulation();
    quick->repository().Set("/Simulation/ODE/UseQuickStep", "T");
    quick->repository().Set("/Simulation/ODE/QuickStepIterations", std::to_string(iterations));
    while (quick->steps() < kEpisodeSteps && quick->Step() == SimulationStatus::kOk) {
    }
    const double drop = start - quick->repository().Get(kHeadPath).as_vector3().y();
    std::fprintf(stderr, "standing 10 s: QuickStep %3d iterations: %s, head drops %.1f mm\n", iterations,
                 quick->status() == SimulationStatus::kOk ? "ok" : quick->message().c_str(), drop * 1e3);
  }
  return ok;
}

// The steps/s of every benchmark, and after the run the ratios issue 3 asks for.
class SummaryReporter : public bench::RateReporter {
 public:
  void PrintSummary() const {
    const double standing = Get("BM_ASeriesStanding");
    const double raw = Get("BM_ASeriesRawOde");
    const double joints = Get("BM_ASeriesRawOdeMotorJoints");
    std::printf("\nsteps/s: standing %.0f, raw ODE %.0f, raw ODE with the motor model's two rows per hinge %.0f\n",
                standing, raw, joints);
    if (standing > 0 && raw > 0) {
      std::printf("motor + sensor model overhead over raw ODE: %.1f %% (target <= 15 %%), real-time factor %.1f\n",
                  (raw / standing - 1) * 100, standing * kDt);
    }
    if (joints > 0 && raw > 0) {
      std::printf("the two rows per hinge, stepped as two: +%.1f %% over raw ODE\n", (raw / joints - 1) * 100);
    }
    for (const int iterations : kQuickStepIterations) {
      const double quick = Get("BM_ASeriesQuickStep/" + std::to_string(iterations));
      if (quick > 0 && standing > 0) {
        std::printf("QuickStep %d iterations: %.0f steps/s, %.2fx dWorldStep, real-time factor %.1f\n", iterations,
                    quick, quick / standing, quick * kDt);
      }
    }
  }
};

}  // namespace
}  // namespace orcs::scene

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!orcs::scene::CheckStanding()) return 1;
  orcs::scene::SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintSummary();
  benchmark::Shutdown();
  return 0;
}
