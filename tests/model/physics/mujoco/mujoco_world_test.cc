// The MuJoCo backend on the small worlds the ODE backend is tested on (tests/model/physics/test_worlds.h): the same
// physical facts, with tolerances for MuJoCo's soft contacts where they differ (docs/model.md, "The MuJoCo
// backend"), and the generated MJCF itself.
#include "model/physics/mujoco/mujoco_world.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <bit>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "model/core/error.h"
#include "model/physics/mujoco/mjcf_export.h"
#include "tests/model/physics/test_worlds.h"

namespace orcs::physics {
namespace {

using ::testing::HasSubstr;
using namespace test_worlds;  // NOLINT: the shared small worlds

TEST(MujocoWorldTest, SphereDroppedOnFloorComesToRest) {
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.5, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 3.0);
  const BodyState s = world->body_state(1);
  EXPECT_NEAR(s.position.y(), 0.05, 2e-3);  // MuJoCo's soft contact sinks by a millimetre or so
  EXPECT_NEAR(s.position.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.position.z(), 0.0, 1e-9);
  EXPECT_LT(s.linear_velocity.norm(), 1e-3);
  EXPECT_LT(s.angular_velocity.norm(), 1e-3);
}

TEST(MujocoWorldTest, ContactsAreReportedWithNormalIntoGeom1) {
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.5, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 1.0);
  ASSERT_FALSE(world->contacts().empty());
  for (const Contact& c : world->contacts()) {
    EXPECT_GT(c.depth, 0.0);
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-9);
    // The normal points into geom1: up when the ball is geom1, down when the floor is.
    const bool ball_first = c.body1 == 1;
    EXPECT_NEAR(c.normal.y(), ball_first ? 1.0 : -1.0, 1e-9);
    EXPECT_NEAR(c.position.y(), 0.0, 2e-3);
  }
}

// Settles a box on the floor with vertical gravity (as the ODE backend's test does); returns the world.
std::unique_ptr<PhysicsWorld> BoxOnSlope(const std::string& box_material, const std::string& floor_material) {
  PhysicsDescription d;
  d.bodies = {Floor(floor_material), Box("Box", {0.1, 0.05, 0.1}, 0.5, box_material, {0, 0.025, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 0.5);
  return world;
}

TEST(MujocoWorldTest, BoxSticksOnSlopeBelowStaticFriction) {
  // Latex on PVC: μ = 0.83462 > tan 30° = 0.577.
  auto world = BoxOnSlope("Latex", "PVC");
  const double x0 = world->body_state(1).position.x();
  RunFor(*world, 2.0, TiltedGravity(30));
  // MuJoCo's friction is a soft constraint: the box creeps (7 mm in 2 s, measured), where ODE's holds to 5 mm.
  EXPECT_LT(std::abs(world->body_state(1).position.x() - x0), 1e-2);
  EXPECT_LT(world->body_state(1).linear_velocity.norm(), 5e-3);
}

TEST(MujocoWorldTest, BoxSlidesOnSlopeAboveFrictionWithDynamicDeceleration) {
  // ABS on PVC: μ = 0.20874 < tan 30°; a = g (sin θ − μ cos θ) = 3.1316 m/s².
  auto world = BoxOnSlope("ABS", "PVC");
  const PhysicsParameters slope = TiltedGravity(30);
  RunFor(*world, 0.5, slope);
  const double v1 = world->body_state(1).linear_velocity.x();
  RunFor(*world, 1.0, slope);
  const double v2 = world->body_state(1).linear_velocity.x();
  const double expected = kG * (std::sin(kPi / 6) - 0.20874 * std::cos(kPi / 6));
  EXPECT_NEAR(v2 - v1, expected, 0.02 * expected);
}

TEST(MujocoWorldTest, HingeAngleFollowsTheAxisRightHandRule) {
  auto world = MakeMujocoWorld(Compile(Pendulum(false, false)));
  RunFor(*world, 0.2);
  EXPECT_LT(world->joint_angle(0), -0.1);  // gravity swings the bob negatively about +z
  EXPECT_NEAR(world->joint_angle(0), BobAngle(*world), 1e-9);  // a reduced coordinate: no drift at all
  EXPECT_LT(world->joint_rate(0), 0.0);
  EXPECT_NEAR(world->joint_rate(0), world->body_state(0).angular_velocity.z(), 1e-9);
}

TEST(MujocoWorldTest, AHingeWhoseChildIsBody2KeepsTheAngleOfBody1AgainstBody2) {
  // The bob hangs from an anchor body: with the bob as body2, the angle is the anchor's against the bob's,
  // the negative of the bob's swing.
  PhysicsDescription d;
  d.bodies = {Box("Anchor", {0.02, 0.02, 0.02}, 1.0, "ABS", {0, 0, 0}), Box("Bob", {0.1, 0.02, 0.02}, 0.1, "ABS", {0.2, 0, 0})};
  JointDescription weld;
  weld.name = "Weld";
  weld.type = JointType::kFixed;
  weld.body1 = "Anchor";
  JointDescription hinge;
  hinge.name = "Pivot";
  hinge.body1 = "Anchor";
  hinge.body2 = "Bob";
  hinge.axis = {0, 0, 1};
  d.joints = {weld, hinge};
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 0.2);
  const Eigen::Vector3d bob = world->body_state(1).position;
  EXPECT_LT(std::atan2(bob.y(), bob.x()), -0.1);
  EXPECT_NEAR(world->joint_angle(1), -std::atan2(bob.y(), bob.x()), 1e-9);
}

TEST(MujocoWorldTest, LimitedHingeStopsAtItsStop) {
  auto world = MakeMujocoWorld(Compile(Pendulum(true, false)));
  double lowest = 0.0;
  for (int i = 0; i < 300; ++i) {
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
    lowest = std::min(lowest, world->joint_angle(0));
  }
  EXPECT_NEAR(world->joint_angle(0), -0.5, 0.01);
  EXPECT_GT(lowest, -0.6);
  EXPECT_LT(std::abs(world->joint_rate(0)), 1e-2);
}

TEST(MujocoWorldTest, MotorReachesCommandedVelocityWithoutLoad) {
  auto world = MakeMujocoWorld(Compile(Pendulum(false, true)));
  world->SetJointMotor(0, 2.0, 10.0);
  RunFor(*world, 0.5, ZeroGravity());
  EXPECT_NEAR(world->joint_rate(0), 2.0, 1e-3);
  EXPECT_NEAR(world->joint_angle(0), 1.0, 0.02);
  world->SetJointMotor(0, -1.0, 10.0);
  RunFor(*world, 0.5, ZeroGravity());
  EXPECT_NEAR(world->joint_rate(0), -1.0, 1e-3);
}

TEST(MujocoWorldTest, MotorTorqueIsLimitedByMaxTorque) {
  PhysicsDescription d = Pendulum(false, true);
  d.bodies[0].position = Eigen::Vector3d::Zero();
  auto world = MakeMujocoWorld(Compile(d));
  const double inertia = 0.1 * (0.1 * 0.1 + 0.02 * 0.02) / 12;
  const double torque = 1e-3;
  world->SetJointMotor(0, 100.0, torque);
  RunFor(*world, 0.1, ZeroGravity());
  EXPECT_NEAR(world->joint_rate(0), torque / inertia * 0.1, 0.01 * torque / inertia * 0.1);
  EXPECT_NEAR(world->joint_motor_torque(0), torque, 1e-12);
}

TEST(MujocoWorldTest, AServoHoldsAgainstGravityAndReportsTheHoldingTorque) {
  const double gravity_torque = 0.1 * kG * 0.2;  // the bob horizontal
  auto world = MakeMujocoWorld(Compile(Pendulum(false, true)));
  EXPECT_EQ(world->joint_motor_torque(0), 0.0);  // before the first step
  world->SetJointMotor(0, 0.0, 1.0);
  RunFor(*world, 1.0);
  EXPECT_LT(std::abs(world->joint_angle(0)), 1e-3);
  EXPECT_NEAR(world->joint_motor_torque(0), gravity_torque, 1e-3 * gravity_torque);

  world->SetJointMotorCompliance(0, 0.5);  // rad/s per N·m: the servo yields at 0.5 · 0.196 rad/s
  RunFor(*world, 0.1);
  // u = v − c·τ with the torque of the step before, through MuJoCo's soft constraint: within 0.2 % (measured 0.16 %)
  EXPECT_NEAR(world->joint_rate(0), -0.5 * world->joint_motor_torque(0), 2e-3 * 0.1);
  EXPECT_LT(world->joint_rate(0), -0.05);
}

TEST(MujocoWorldTest, AddedTorqueActsForOneStepAndUsesTheTotalMass) {
  PhysicsDescription d = Pendulum(false, false);
  d.bodies[0].position = Eigen::Vector3d::Zero();
  GeomDescription pad = MakeGeom(Shape::kBox, {0.01, 0.01, 0.01}, "Latex");
  pad.name = "pad";
  pad.mass = 0.3;
  pad.offset = {0.05, 0, 0};
  d.bodies[0].geoms.push_back(pad);
  auto world = MakeMujocoWorld(Compile(d));
  const double inertia = 0.4 * (0.1 * 0.1 + 0.02 * 0.02) / 12;
  world->AddJointTorque(0, 0.002);
  RunFor(*world, kDt, ZeroGravity());
  const double rate = 0.002 / inertia * kDt;
  EXPECT_NEAR(world->joint_rate(0), rate, 1e-6 * rate);
  RunFor(*world, kDt, ZeroGravity());
  EXPECT_NEAR(world->joint_rate(0), rate, 1e-6 * rate);
}

TEST(MujocoWorldTest, JointFrictionHoldsThePendulumAboveTheGravityTorque) {
  const double gravity_torque = 0.1 * kG * 0.2;
  auto held = MakeMujocoWorld(Compile(Pendulum(false, false)));
  held->SetJointFriction(0, 2.0 * gravity_torque);
  RunFor(*held, 1.0);
  EXPECT_LT(std::abs(held->joint_angle(0)), 1e-2);  // MuJoCo's friction loss is soft: it creeps a little

  auto swinging = MakeMujocoWorld(Compile(Pendulum(false, false)));
  swinging->SetJointFriction(0, 0.5 * gravity_torque);
  RunFor(*swinging, 1.0);
  EXPECT_LT(swinging->joint_angle(0), -0.3);
}

TEST(MujocoWorldTest, FixedJointWeldsToTheWorld) {
  PhysicsDescription d;
  d.bodies = {Box("Lamp", {0.1, 0.1, 0.1}, 1.0, "ABS", {0, 1, 0})};
  JointDescription weld;
  weld.name = "Weld";
  weld.type = JointType::kFixed;
  weld.body1 = "Lamp";
  d.joints.push_back(weld);
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 1.0);
  EXPECT_EQ(world->body_state(0).position.y(), 1.0);  // welded by nesting: exactly in place
  EXPECT_EQ(world->joint_angle(0), 0.0);
}

TEST(MujocoWorldTest, ShelfStopsTheBallAndExcludedPairsReportContactsButPassThrough) {
  auto stopped = MakeMujocoWorld(Compile(BallAboveShelf()));
  RunFor(*stopped, 2.0);
  EXPECT_NEAR(stopped->body_state(2).position.y(), 0.36, 2e-3);

  PhysicsDescription d = BallAboveShelf();
  d.contact_exclusions.emplace_back("Shelf", "Ball");
  auto world = MakeMujocoWorld(Compile(d));
  int excluded_contacts = 0;
  for (int i = 0; i < 200; ++i) {
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
    for (const Contact& c : world->contacts()) excluded_contacts += c.excluded ? 1 : 0;
  }
  EXPECT_GT(excluded_contacts, 0);
  EXPECT_NEAR(world->body_state(2).position.y(), 0.05, 2e-3);  // through the shelf onto the floor
}

TEST(MujocoWorldTest, ResetGivesBitIdenticalTrajectories) {
  PhysicsDescription d;
  d.bodies = {Floor(), Box("Block", {0.1, 0.05, 0.08}, 0.3, "ABS", {0, 0.3, 0})};
  d.bodies[1].orientation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized());
  auto world = MakeMujocoWorld(Compile(d));
  const auto trace = [&world] {
    std::vector<double> values;
    for (int i = 0; i < 150; ++i) {
      EXPECT_EQ(world->Step(kDt, {}), StepStatus::kOk);
      const BodyState s = world->body_state(1);
      for (double v : {s.position.x(), s.position.y(), s.orientation.w(), s.angular_velocity.z()}) values.push_back(v);
    }
    return values;
  };
  const std::vector<double> first = trace();
  world->Reset();
  const std::vector<double> second = trace();
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) ASSERT_EQ(std::bit_cast<std::uint64_t>(first[i]), std::bit_cast<std::uint64_t>(second[i])) << i;

  auto other = MakeMujocoWorld(Compile(d));  // another world of the same description, on another thread
  std::vector<double> third;
  std::thread([&] { world.swap(other); third = trace(); }).join();
  EXPECT_EQ(first, third);
}

TEST(MujocoWorldTest, SetBodyStateMovesAFreeBody) {
  PhysicsDescription d;
  d.bodies = {Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.5, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  BodyState state;
  state.position = {1, 2, 3};
  state.orientation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  state.linear_velocity = {0.5, 0, 0};
  state.angular_velocity = {0, 0, 2};
  world->SetBodyState(0, state);
  ASSERT_EQ(world->Step(kDt, ZeroGravity()), StepStatus::kOk);  // no force: it coasts
  const BodyState read = world->body_state(0);
  EXPECT_TRUE(read.position.isApprox(state.position + kDt * state.linear_velocity, 1e-12));
  EXPECT_TRUE(read.linear_velocity.isApprox(state.linear_velocity, 1e-12));
  EXPECT_TRUE(read.angular_velocity.isApprox(state.angular_velocity, 1e-12));
}

TEST(MujocoWorldTest, PosingAHingedBodyTurnsItsHinge) {
  // The bob turned rigidly by 0.3 rad about the pivot, as Simulation::SetAgentJointAngles poses a limb.
  auto world = MakeMujocoWorld(Compile(Pendulum(false, false)));
  const Eigen::AngleAxisd turn(0.3, Eigen::Vector3d::UnitZ());
  BodyState bob = world->body_state(0);
  bob.position = turn * bob.position;
  bob.orientation = turn * bob.orientation;
  world->SetBodyState(0, bob);
  EXPECT_EQ(world->body_state(0).position, bob.position);  // read back before it is applied
  EXPECT_NEAR(world->joint_angle(0), 0.3, 1e-12);
  EXPECT_TRUE(world->body_state(0).position.isApprox(bob.position, 1e-12));
}

TEST(MujocoWorldTest, HugeVelocityIsUnstable) {
  PhysicsDescription d;
  d.bodies = {Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.5, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  BodyState fast = world->body_state(0);
  fast.linear_velocity = {1e4, 0, 0};
  world->SetBodyState(0, fast);
  EXPECT_EQ(world->Step(kDt, {}), StepStatus::kUnstable);
  EXPECT_EQ(world->Step(kDt, {}), StepStatus::kUnstable);  // until Reset
  world->Reset();
  EXPECT_EQ(world->Step(kDt, {}), StepStatus::kOk);
}

TEST(MujocoWorldTest, AJointLoopIsRefusedNamingTheJoint) {
  PhysicsDescription d = Pendulum(false, false);
  JointDescription second = d.joints[0];
  second.name = "SecondPivot";
  d.joints.push_back(second);
  try {
    MakeMujocoWorld(Compile(d));
    FAIL() << "a loop was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("joint 'SecondPivot' closes a kinematic loop"));
  }
}

TEST(MujocoWorldTest, TheExportedMjcfLoadsInMujocoWithTheSameBodiesJointsAndMass) {
  PhysicsDescription d = BallAboveShelf();
  PhysicsDescription pendulum = Pendulum(true, true);
  d.bodies.push_back(pendulum.bodies[0]);
  d.joints = pendulum.joints;
  const std::shared_ptr<const PhysicsModel> model = Compile(d);
  const std::string xml = ExportMjcf(*model);
  char error[1000] = "";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  ASSERT_EQ(mj_makeEmptyFileVFS(&vfs, "x.xml", static_cast<int>(xml.size())), 0);
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[vfs.nfile - 1]));
  mjModel* m = mj_loadXML("x.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nbody, 3);  // the world, the ball, the bob
  EXPECT_EQ(m->njnt, 2);   // the ball's free joint, the pivot
  EXPECT_EQ(m->ntendon, 1);  // the pivot's motor
  EXPECT_NEAR(m->body_mass[mj_name2id(m, mjOBJ_BODY, "Ball")], 0.1, 1e-15);
  EXPECT_EQ(m->jnt_limited[mj_name2id(m, mjOBJ_JOINT, "Pivot")], 1);
  mj_deleteModel(m);
}

}  // namespace
}  // namespace orcs::physics
