// What only the MuJoCo backend has, on the small worlds of test_worlds.h: hinges whose child is body 2, the servo's
// holding torque and compliance through MuJoCo's soft constraint, posing bodies through SetBodyState, the refusal of
// joint loops, the generated MJCF itself, and (disabled) two known defects. The physical facts every backend shows are
// in ../physics_world_test.cc, run on ODE and on MuJoCo, with MuJoCo's tolerances for its soft contacts where they
// differ (docs/model.md, "The MuJoCo backend").
#include "model/physics/mujoco/mujoco_world.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "model/core/error.h"
#include "model/physics/mujoco/mjcf_export.h"
#include "tests/model/physics/test_worlds.h"

namespace orcs::physics {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using namespace test_worlds;  // NOLINT: the shared small worlds

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
  // u = v − c·τ with this step's torque (the row's own softness: implicit, as ODE's CFM)
  EXPECT_NEAR(world->joint_rate(0), -0.5 * world->joint_motor_torque(0), 1e-9);
  EXPECT_LT(world->joint_rate(0), -0.05);
}

// DISABLED: a known defect of MuJoCo 2.2.2 itself, found when the backend's tests joined the ODE backend's in
// ../physics_world_test.cc. Enable it once it passes, and then drop Engine::slides_flat there.

TEST(MujocoWorldTest, DISABLED_ABoxSlidingDownASlopeStaysOnIt) {
  // ABS on PVC down 30°, as in PhysicsWorldTest.BoxSlidesOnSlopeAboveFrictionWithDynamicDeceleration. Measured:
  // the box hops up to 6.7 cm off the slope (|v_y| up to 0.8 m/s) and spins at up to 28 rad/s; ODE's stays within
  // 14 µm and 1e-5 m/s. Raw MuJoCo does the same with no orcs code (the box and plane as plain MJCF, μ = 0.4, the
  // same gravity switch): 4.2 cm and 32 rad/s at 10 ms steps, with the elliptic cone 5.0 cm, at 2 ms steps still
  // 2 mm and 6 rad/s, softer contacts (solref 0.05) 1.3 cm. So it is MuJoCo's fast sliding box contact at this
  // step size, not the backend's (docs/model.md).
  PhysicsDescription d;
  d.bodies = {Floor("PVC"), Box("Box", {0.1, 0.05, 0.1}, 0.5, "ABS", {0, 0.025, 0})};
  auto world = MakeMujocoWorld(Compile(d));
  RunFor(*world, 0.5);
  const double y0 = world->body_state(1).position.y();
  for (int i = 0; i < 150; ++i) {
    ASSERT_EQ(world->Step(kDt, TiltedGravity(30)), StepStatus::kOk);
    const BodyState s = world->body_state(1);
    ASSERT_NEAR(s.position.y(), y0, 1e-3) << "step " << i;
    ASSERT_LT(std::abs(s.linear_velocity.y()), 1e-3) << "step " << i;
    ASSERT_LT(s.angular_velocity.norm(), 1e-2) << "step " << i;
  }
}

// test_worlds.h's out-of-plane chain: at step 69 of Trajectory its jointed links Link1 (Latex) and Link2 (ABS),
// a pair the material table makes frictionless while they slide, touch. A μ = 0 pyramid has rows of zero weight
// whose regularisation is 0, and the step failed with "bad number in qacc" until such contacts became
// normal-only (condim 1). It now runs as on ODE.
TEST(MujocoWorldTest, AChainWhoseJointedLinksTouchWithoutFrictionKeepsStepping) {
  auto world = MakeMujocoWorld(Compile(Chain()));
  bool frictionless_pair_touched = false;
  for (int i = 0; i < 200; ++i) {  // Trajectory's commands
    world->SetJointMotor(0, 2.0 * std::sin(0.05 * i), 0.05);
    world->SetJointMotor(1, -1.0, 0.02);
    world->SetJointFriction(1, 0.001);
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk) << "step " << i << ": " << world->last_error();
    for (const Contact& c : world->contacts()) frictionless_pair_touched |= c.body1 + c.body2 == 5;  // links 2, 3
  }
  EXPECT_TRUE(frictionless_pair_touched);
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

// Raw MuJoCo's model of an exported MJCF text; nullptr with `error` set when MuJoCo refuses it.
mjModel* LoadMjcf(const std::string& xml, char (&error)[1000]) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  if (mj_makeEmptyFileVFS(&vfs, "x.xml", static_cast<int>(xml.size())) != 0) return nullptr;
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[vfs.nfile - 1]));
  mjModel* m = mj_loadXML("x.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  return m;
}

// Where the ball of BallAboveShelf ends after 2 s of raw MuJoCo on the exported model, m above the floor.
double RawBallHeightAfterTwoSeconds(const std::string& xml) {
  char error[1000] = "";
  mjModel* m = LoadMjcf(xml, error);
  if (m == nullptr) throw std::runtime_error(error);
  mjData* d = mj_makeData(m);
  while (d->time < 2.0) mj_step(m, d);
  const double height = d->xpos[3 * mj_name2id(m, mjOBJ_BODY, "Ball") + 1];
  mj_deleteData(d);
  mj_deleteModel(m);
  return height;
}

TEST(MujocoWorldTest, TheExportedMjcfLoadsInMujocoWithTheSameBodiesJointsAndMass) {
  PhysicsDescription d = BallAboveShelf();
  PhysicsDescription pendulum = Pendulum(true, true);
  d.bodies.push_back(pendulum.bodies[0]);
  d.joints = pendulum.joints;
  const std::shared_ptr<const PhysicsModel> model = Compile(d);
  char error[1000] = "";
  mjModel* m = LoadMjcf(ExportMjcf(*model), error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nbody, 3);  // the world, the ball, the bob
  EXPECT_EQ(m->njnt, 2);   // the ball's free joint, the pivot
  EXPECT_EQ(m->ntendon, 1);  // the pivot's motor
  EXPECT_NEAR(m->body_mass[mj_name2id(m, mjOBJ_BODY, "Ball")], 0.1, 1e-15);
  EXPECT_EQ(m->jnt_limited[mj_name2id(m, mjOBJ_JOINT, "Pivot")], 1);
  mj_deleteModel(m);
}

// With the exclusion list as <exclude> pairs (as the world compiles it and `--export-mjcf` writes it) raw MuJoCo
// lets the ball fall through the shelf as the world does, and still stops it on the floor: the static shelf is its
// own body there.
TEST(MujocoWorldTest, TheExportWithExclusionsLetsRawMujocoPassThroughAnExcludedPair) {
  PhysicsDescription d = BallAboveShelf();
  d.contact_exclusions.emplace_back("Shelf", "Ball");
  const std::shared_ptr<const PhysicsModel> model = Compile(d);
  const std::string with = ExportMjcf(*model, {.exclusions = true});
  EXPECT_THAT(with, HasSubstr("<exclude body1=\"Shelf\" body2=\"Ball\"/>"));
  EXPECT_NEAR(RawBallHeightAfterTwoSeconds(with), 0.05, 1e-3);  // on the floor, under the shelf

  const std::string without = ExportMjcf(*model);
  EXPECT_THAT(without, Not(HasSubstr("<exclude")));
  EXPECT_NEAR(RawBallHeightAfterTwoSeconds(without), 0.36, 1e-3);  // raw MuJoCo alone would stop it on the shelf
}

}  // namespace
}  // namespace orcs::physics
