// Cost of the engine-independent physics layer over raw ODE calls, on the same scene: a stack of 20 hinged
// 5 cm boxes standing on a PVC floor. Items/s = simulation steps per second. Target: overhead < 10 %.
//
// Both sides build the scene with the same ODE calls in the same order and use the same contact rule, so
// their trajectories are bit-identical (checked before the benchmarks run): the comparison measures the
// layer's bookkeeping only, never a different simulation.
//
//   physics_layer_bench --benchmark_repetitions=5 --benchmark_min_time=2
#include <benchmark/benchmark.h>
#include <ode/ode.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "model/physics/ode/ode_joints.h"
#include "model/physics/ode/ode_world.h"
#include "model/physics/physics_model.h"

namespace orcs::physics {
namespace {

constexpr int kBoxes = 20;
constexpr double kEdge = 0.05;           // m, cube edge
constexpr double kGap = 0.002;           // m between consecutive boxes
constexpr double kBoxMass = 0.1;         // kg
constexpr double kLimit = std::numbers::pi / 4;  // ±45° hinge stops
constexpr double kDt = 0.01;             // s
constexpr int kEpisodeSteps = 300;       // 3 s: the stack topples and comes to rest on the floor
// A small lean so that the stack falls the same way every time instead of balancing on round-off.
constexpr double kLean = 0.002;          // m of x offset per box

// ABS boxes on PVC (spec/aseries.md §7): the two material pairs of this scene.
constexpr double kAbsPvc = 0.20874;         // static = dynamic
constexpr double kAbsAbsStatic = 0.8097;
constexpr double kAbsAbsDynamic = 0.5677;
constexpr double kRestitution = 0.1;        // both pairs

Eigen::Vector3d BoxCentre(int i) { return {kLean * i, kEdge / 2 + i * (kEdge + kGap), 0.0}; }
Eigen::Vector3d HingeAnchor(int i) { return BoxCentre(i) + Eigen::Vector3d(0, (kEdge + kGap) / 2, 0); }
Eigen::Vector3d HingeAxis(int i) { return i % 2 == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ(); }

PhysicsDescription StackDescription() {
  PhysicsDescription d;
  BodyDescription floor;
  floor.name = "Floor";
  floor.dynamic = false;
  GeomDescription plane;
  plane.shape = Shape::kPlane;
  plane.material = "PVC";
  floor.geoms.push_back(plane);
  d.bodies.push_back(floor);
  for (int i = 0; i < kBoxes; ++i) {
    BodyDescription box;
    box.name = "Box" + std::to_string(i);
    box.mass = kBoxMass;
    box.position = BoxCentre(i);
    GeomDescription cube;
    cube.size = {kEdge, kEdge, kEdge};
    cube.material = "ABS";
    box.geoms.push_back(cube);
    d.bodies.push_back(box);
  }
  for (int i = 0; i + 1 < kBoxes; ++i) {
    JointDescription hinge;
    hinge.name = "Hinge" + std::to_string(i);
    hinge.body1 = "Box" + std::to_string(i + 1);
    hinge.body2 = "Box" + std::to_string(i);
    hinge.anchor = HingeAnchor(i);
    hinge.axis = HingeAxis(i);
    hinge.limited = true;
    hinge.lo = -kLimit;
    hinge.hi = kLimit;
    d.joints.push_back(hinge);
    d.contact_exclusions.emplace_back(hinge.body1, hinge.body2);  // jointed neighbours touch at the stops
  }
  return d;
}

// The same scene in raw ODE, written as a user without the layer would: the same calls in the same order,
// the same contact surface, the friction rule specialised to this scene's two material pairs.
class RawOdeStack {
 public:
  RawOdeStack() {
    const PhysicsParameters p;
    world_ = dWorldCreate();
    dWorldSetERP(world_, p.erp);
    dWorldSetCFM(world_, p.cfm);
    dWorldSetGravity(world_, p.gravity.x(), p.gravity.y(), p.gravity.z());
    dWorldSetContactSurfaceLayer(world_, p.contact_surface_layer);
    dWorldSetContactMaxCorrectingVel(world_, p.contact_max_correcting_velocity);
    space_ = dSimpleSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    dGeomID floor = dCreatePlane(space_, 0, 1, 0, 0);
    dGeomSetData(floor, IndexToData(-1));
    for (int i = 0; i < kBoxes; ++i) {
      dBodyID body = dBodyCreate(world_);
      const Eigen::Vector3d c = BoxCentre(i);
      dBodySetPosition(body, c.x(), c.y(), c.z());
      const dQuaternion identity = {1, 0, 0, 0};
      dBodySetQuaternion(body, identity);
      dMass mass;
      dMassSetZero(&mass);
      dMassSetBoxTotal(&mass, kBoxMass, kEdge, kEdge, kEdge);
      dBodySetMass(body, &mass);
      dGeomID geom = dCreateBox(space_, kEdge, kEdge, kEdge);
      dGeomSetBody(geom, body);
      dGeomSetData(geom, IndexToData(i));
      bodies_[i] = body;
    }
    for (int i = 0; i + 1 < kBoxes; ++i) {
      dJointID hinge = dJointCreateHinge(world_, nullptr);
      dJointAttach(hinge, bodies_[i + 1], bodies_[i]);
      const Eigen::Vector3d a = HingeAnchor(i);
      const Eigen::Vector3d x = HingeAxis(i);
      dJointSetHingeAnchor(hinge, a.x(), a.y(), a.z());
      dJointSetHingeAxis(hinge, x.x(), x.y(), x.z());
      dJointSetHingeParam(hinge, dParamLoStop, -kLimit);
      dJointSetHingeParam(hinge, dParamHiStop, kLimit);
      dJointSetHingeParam(hinge, dParamVel, 0.0);
      dJointSetHingeParam(hinge, dParamFMax, 0.0);
    }
  }
  ~RawOdeStack() {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }
  RawOdeStack(const RawOdeStack&) = delete;
  RawOdeStack& operator=(const RawOdeStack&) = delete;

  bool Step() {
    dSpaceCollide(space_, this, &RawOdeStack::NearCallback);
    const int ok = dWorldStep(world_, kDt);
    dJointGroupEmpty(contacts_);
    return ok != 0;
  }
  const dReal* position(int box) const { return dBodyGetPosition(bodies_[box]); }

 private:
  static void* IndexToData(int index) { return reinterpret_cast<void*>(static_cast<std::intptr_t>(index)); }
  static int DataToIndex(void* data) { return static_cast<int>(reinterpret_cast<std::intptr_t>(data)); }
  static void NearCallback(void* data, dGeomID o1, dGeomID o2) { static_cast<RawOdeStack*>(data)->Collide(o1, o2); }

  void Collide(dGeomID o1, dGeomID o2) {
    const int i1 = DataToIndex(dGeomGetData(o1));
    const int i2 = DataToIndex(dGeomGetData(o2));
    const int n = dCollide(o1, o2, PhysicsParameters::kMaxContactPoints, points_.data(), sizeof(dContactGeom));
    const bool neighbours = std::abs(i1 - i2) == 1 && i1 >= 0 && i2 >= 0;
    const bool floor_pair = i1 < 0 || i2 < 0;
    dBodyID b1 = dGeomGetBody(o1);
    dBodyID b2 = dGeomGetBody(o2);
    const PhysicsParameters p;
    for (int k = 0; k < n; ++k) {
      if (std::abs(points_[k].depth) < p.min_contact_depth || neighbours) continue;
      const double mu = floor_pair ? kAbsPvc : BoxBoxFriction(points_[k], b1, b2, p.static_friction_speed);
      physics::CreateContactJoint(world_, contacts_, points_[k], b1, b2, mu, {.restitution = kRestitution}, p);
    }
  }

  static double BoxBoxFriction(const dContactGeom& point, dBodyID b1, dBodyID b2, double static_speed) {
    dVector3 v1;
    dVector3 v2;
    dBodyGetPointVel(b1, point.pos[0], point.pos[1], point.pos[2], v1);
    dBodyGetPointVel(b2, point.pos[0], point.pos[1], point.pos[2], v2);
    const Eigen::Vector3d relative(v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]);
    const Eigen::Vector3d normal(point.normal[0], point.normal[1], point.normal[2]);
    const Eigen::Vector3d tangential = relative - relative.dot(normal) * normal;
    return tangential.squaredNorm() < static_speed * static_speed ? kAbsAbsStatic : kAbsAbsDynamic;
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::array<dBodyID, kBoxes> bodies_{};
  std::array<dContactGeom, PhysicsParameters::kMaxContactPoints> points_{};
};

void BM_PhysicsLayer(benchmark::State& state) {
  const auto model = std::make_shared<const PhysicsModel>(StackDescription());
  auto world = MakeOdeWorld(model);
  const PhysicsParameters parameters;
  int step = 0;
  for (auto _ : state) {
    if (step == kEpisodeSteps) {
      state.PauseTiming();
      world->Reset();
      state.ResumeTiming();
      step = 0;
    }
    if (world->Step(kDt, parameters) != StepStatus::kOk) {
      state.SkipWithError(("step failed: " + world->last_error()).c_str());
      break;
    }
    ++step;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_RawOde(benchmark::State& state) {
  dInitODE2(0);
  dAllocateODEDataForThread(dAllocateMaskAll);
  auto stack = std::make_unique<RawOdeStack>();
  int step = 0;
  for (auto _ : state) {
    if (step == kEpisodeSteps) {
      state.PauseTiming();
      stack = std::make_unique<RawOdeStack>();
      state.ResumeTiming();
      step = 0;
    }
    if (!stack->Step()) {
      state.SkipWithError("dWorldStep failed");
      break;
    }
    ++step;
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_PhysicsLayer)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RawOde)->Unit(benchmark::kMicrosecond);

// Runs one episode on both sides and compares every box position after every step, bit for bit.
bool SameTrajectories() {
  auto world = MakeOdeWorld(std::make_shared<const PhysicsModel>(StackDescription()));
  RawOdeStack raw;
  const PhysicsParameters parameters;
  for (int step = 0; step < kEpisodeSteps; ++step) {
    if (world->Step(kDt, parameters) != StepStatus::kOk || !raw.Step()) {
      std::fprintf(stderr, "step %d failed: %s\n", step, world->last_error().c_str());
      return false;
    }
    for (int i = 0; i < kBoxes; ++i) {
      const Eigen::Vector3d layer = world->body_state(i + 1).position;
      const dReal* ode = raw.position(i);
      if (layer.x() != ode[0] || layer.y() != ode[1] || layer.z() != ode[2]) {
        std::fprintf(stderr, "trajectories differ at step %d, box %d\n", step, i);
        return false;
      }
    }
  }
  const Eigen::Vector3d top = world->body_state(kBoxes).position;
  std::fprintf(stderr, "layer and raw ODE: bit-identical over %d steps; top box ends at (%.3f, %.3f, %.3f) m\n",
               kEpisodeSteps, top.x(), top.y(), top.z());
  return true;
}

}  // namespace
}  // namespace orcs::physics

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!orcs::physics::SameTrajectories()) return 1;  // a different simulation would make the figures meaningless
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
