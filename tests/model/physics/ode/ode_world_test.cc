// What only the ODE backend has, on the small worlds of test_worlds.h: shallow contact points dropped, restitution,
// the static/dynamic friction switch and friction scaling, geom placement, the combined motor rows, motor compliance,
// added body inertia, ODE's error handler and the QuickStep solver. The physical facts every backend shows are in
// ../physics_world_test.cc, run on ODE and on MuJoCo.
#include "model/physics/ode/ode_world.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "model/physics/physics_model.h"
#include "tests/model/physics/test_worlds.h"

namespace orcs::physics {
namespace {

using ::testing::HasSubstr;
using namespace test_worlds;  // NOLINT: the shared small worlds

TEST(OdeWorldTest, ShallowContactPointsAreDropped) {
  // Points shallower than min_contact_depth make no contact, so the ball sinks until it is that deep.
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.1, 0})};
  auto world = MakeOdeWorld(Compile(d));
  PhysicsParameters p;
  p.min_contact_depth = 0.005;
  RunFor(*world, 2.0, p);
  EXPECT_LT(world->body_state(1).position.y(), 0.05 - 0.004);
  EXPECT_GT(world->body_state(1).position.y(), 0.05 - 0.008);
  for (const Contact& c : world->contacts()) EXPECT_GE(c.depth, 0.005);
}

// ODE's default step threading is one per process and takes no lock: two threads stepping two worlds at once
// corrupted its job list and a step never returned (orcs-robot's twin beside the servo-bus emulator's simulated
// shafts). Each world has its own now; both threads get the bits one thread gets.
TEST(OdeWorldTest, WorldsSteppedOnTwoThreadsAtOnceGiveTheBitsOfOne) {
  PhysicsDescription d;
  d.bodies = {Floor()};
  for (int i = 0; i < 8; ++i) {  // eight islands: many jobs per step
    d.bodies.push_back(Sphere("Ball" + std::to_string(i), 0.05, 0.1, "ABS", {0.3 * i, 0.1 + 0.02 * i, 0}));
  }
  const auto model = Compile(d);
  const PhysicsParameters p;
  const auto heights = [](const PhysicsWorld& world) {
    std::vector<double> y;
    for (int b = 1; b < 9; ++b) y.push_back(world.body_state(b).position.y());
    return y;
  };
  auto alone = MakeOdeWorld(model);
  RunFor(*alone, 30.0, p);
  const std::vector<double> expected = heights(*alone);
  for (int round = 0; round < 4; ++round) {
    auto first = MakeOdeWorld(model);
    auto second = MakeOdeWorld(model);
    std::thread a([&] { RunFor(*first, 30.0, p); });
    std::thread b([&] { RunFor(*second, 30.0, p); });
    a.join();
    b.join();
    EXPECT_EQ(heights(*first), expected) << "round " << round;
    EXPECT_EQ(heights(*second), expected) << "round " << round;
  }
}

TEST(OdeWorldTest, RestitutionFollowsTheMaterialTable) {
  // Drop from 0.2 m (bottom); Default on PVC bounces with 0.5, ABS on PVC with 0.1.
  auto rebound = [](const std::string& material) {
    PhysicsDescription d;
    d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, material, {0, 0.25, 0})};
    auto world = MakeOdeWorld(Compile(d));
    double apex = 0.0;
    bool bounced = false;
    for (int i = 0; i < 100; ++i) {
      EXPECT_EQ(world->Step(kDt, {}), StepStatus::kOk);
      const BodyState s = world->body_state(1);
      if (s.linear_velocity.y() > 0.0) bounced = true;
      if (bounced) apex = std::max(apex, s.position.y() - 0.05);
      if (bounced && s.linear_velocity.y() < 0.0) break;
    }
    return apex;
  };
  const double bouncy = rebound("Default");
  const double dull = rebound("ABS");
  // e² · h = 0.25 · 0.2 = 0.05 m, blurred by the 1 cm step and the contact ERP.
  EXPECT_GT(bouncy, 0.03);
  EXPECT_LT(bouncy, 0.07);
  EXPECT_LT(dull, 0.3 * bouncy);
}

// Settles a box on the floor with vertical gravity; tilt the gravity (TiltedGravity) to make the floor a slope.
std::unique_ptr<PhysicsWorld> BoxOnSlope(const std::string& box_material, const std::string& floor_material) {
  PhysicsDescription d;
  d.bodies = {Floor(floor_material), Box("Box", {0.1, 0.05, 0.1}, 0.5, box_material, {0, 0.025, 0})};
  auto world = MakeOdeWorld(Compile(d));
  RunFor(*world, 0.5);
  return world;
}

TEST(OdeWorldTest, StaticCoefficientHoldsUntilSlidingThenDynamicApplies) {
  // ABS on Carpet: static 0.55167, dynamic 0.47116. tan 26.5° = 0.4986 lies between them.
  const PhysicsParameters slope = TiltedGravity(26.5);
  auto at_rest = BoxOnSlope("ABS", "Carpet");
  RunFor(*at_rest, 1.0, slope);
  EXPECT_LT(at_rest->body_state(1).linear_velocity.norm(), 5e-3);

  auto kicked = BoxOnSlope("ABS", "Carpet");
  BodyState s = kicked->body_state(1);
  s.linear_velocity = {0.5, 0, 0};
  kicked->SetBodyState(1, s);
  RunFor(*kicked, 1.0, slope);
  const double angle = 26.5 * kPi / 180;
  const double a = kG * (std::sin(angle) - 0.47116 * std::cos(angle));  // 0.241 m/s², speeding up
  EXPECT_NEAR(kicked->body_state(1).linear_velocity.x(), 0.5 + a * 1.0, 0.02);
}

TEST(OdeWorldTest, FrictionScalingScalesOnlyTheDynamicCoefficient) {
  PhysicsParameters slope = TiltedGravity(35);
  slope.friction_scaling = 0.5;
  auto world = BoxOnSlope("ABS", "Carpet");
  RunFor(*world, 0.5, slope);
  const double v1 = world->body_state(1).linear_velocity.x();
  RunFor(*world, 1.0, slope);
  const double v2 = world->body_state(1).linear_velocity.x();
  const double angle = 35 * kPi / 180;
  const double expected = kG * (std::sin(angle) - 0.5 * 0.47116 * std::cos(angle));
  EXPECT_NEAR(v2 - v1, expected, 0.02 * expected);
}

TEST(OdeWorldTest, NonCollidingGeomFallsThroughTheFloor) {
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ghost", 0.05, 0.1, "ABS", {0, 0.1, 0})};
  d.bodies[1].geoms[0].collides = false;
  auto world = MakeOdeWorld(Compile(d));
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
    EXPECT_TRUE(world->contacts().empty());
  }
  EXPECT_LT(world->body_state(1).position.y(), -4.0);
}

TEST(OdeWorldTest, StaticGeomsArePlacedByBodyPoseAndOffset) {
  // A shelf body at the origin turned 90° about z, whose geom sits 0.3 m along the body's x: in the world
  // the geom is at (0, 0.3, 0) and 1 m wide in x (its local y).
  PhysicsDescription d = BallAboveShelf();
  d.bodies[1].position = Eigen::Vector3d::Zero();
  d.bodies[1].orientation = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ());
  d.bodies[1].geoms[0].size = {0.02, 1, 1};
  d.bodies[1].geoms[0].offset = {0.3, 0, 0};
  d.bodies[2].position.x() = 0.3;  // still over the shelf only if the rotation was applied
  auto world = MakeOdeWorld(Compile(d));
  RunFor(*world, 2.0);
  EXPECT_NEAR(world->body_state(2).position.y(), 0.36, 1.5e-3);
}

TEST(OdeWorldTest, TiltedPlaneNormalIsTheBodyYAxis) {
  // Floor turned 90° about z: normal (−1, 0, 0); the plane passes through x = 0.2.
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, "ABS", {-0.3, 1, 0})};
  d.bodies[0].orientation = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ());
  d.bodies[0].position = {0.2, 0, 0};
  auto world = MakeOdeWorld(Compile(d));
  PhysicsParameters sideways;
  sideways.gravity = {kG, 0, 0};
  RunFor(*world, 2.0, sideways);
  EXPECT_NEAR(world->body_state(1).position.x(), 0.15, 1.5e-3);
}

TEST(OdeWorldTest, GeomOffsetsTurnWithTheBody) {
  // A dumbbell: the main sphere 0.15 m along −x of the body frame, an extra one 0.15 m along +x; the body is
  // turned 90° about y, so in the world they end up at z = +0.15 and z = −0.15 and it rests on both.
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Bell", 0.05, 0.1, "ABS", {0, 0.2, 0})};
  d.bodies[1].orientation = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY());
  d.bodies[1].geoms[0].offset = {-0.15, 0, 0};
  GeomDescription other = MakeGeom(Shape::kSphere, {0.05, 0, 0}, "ABS");
  other.name = "other";
  other.mass = 0.1;
  other.offset = {0.15, 0, 0};
  d.bodies[1].geoms.push_back(other);
  auto world = MakeOdeWorld(Compile(d));
  RunFor(*world, 1.5);
  bool touched[2] = {false, false};
  for (const Contact& c : world->contacts()) {
    const int geom = c.body1 == 1 ? c.geom1 : c.geom2;
    ASSERT_TRUE(geom == 1 || geom == 2);
    touched[geom - 1] = true;
    EXPECT_NEAR(c.position.z(), geom == 1 ? 0.15 : -0.15, 2e-3);
    EXPECT_NEAR(c.position.x(), 0.0, 2e-3);
  }
  EXPECT_TRUE(touched[0]);
  EXPECT_TRUE(touched[1]);
  EXPECT_NEAR(world->body_state(1).position.y(), 0.05, 1.5e-3);
}

TEST(OdeWorldTest, BodyStateQuaternionIsWxyz) {
  PhysicsDescription d;
  d.bodies = {Box("Spinner", {0.1, 0.1, 0.1}, 1.0, "ABS", {0, 0, 0})};
  auto world = MakeOdeWorld(Compile(d));
  BodyState s;
  s.angular_velocity = {0, 0, 1};  // 1 rad/s about +z
  world->SetBodyState(0, s);
  RunFor(*world, 1.0, ZeroGravity());
  const Eigen::Quaterniond q = world->body_state(0).orientation;
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(std::abs(q.dot(expected)), 1.0, 1e-6) << q.coeffs().transpose();

  const Eigen::Quaterniond turned(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  s.orientation = turned;
  s.position = {1, 2, 3};
  s.linear_velocity = {0.1, 0.2, 0.3};
  world->SetBodyState(0, s);
  const BodyState back = world->body_state(0);
  EXPECT_TRUE(back.orientation.coeffs().isApprox(turned.coeffs(), 1e-12));
  EXPECT_EQ(back.position, s.position);
  EXPECT_EQ(back.linear_velocity, s.linear_velocity);
  EXPECT_EQ(back.angular_velocity, s.angular_velocity);
}

// The motor model's commands on both hinges of the chain: a velocity-driven motor, sometimes at its torque limit,
// and a friction brake that grows with the rate, so that every hinge is in turn sliding, held and at a stop.
std::vector<double> BrakedTrajectory(PhysicsWorld& world, int steps, const PhysicsParameters& parameters) {
  std::vector<double> out;
  for (int i = 0; i < steps; ++i) {
    for (int j = 0; j < 2; ++j) {
      world.SetJointMotor(j, (j == 0 ? 3.0 : -1.5) * std::sin(0.03 * i + j), j == 0 ? 0.05 : 0.004);
      world.SetJointFriction(j, 0.001 + 0.01 * std::abs(world.joint_rate(j)));
    }
    EXPECT_EQ(world.Step(kDt, parameters), StepStatus::kOk);
    for (int b = 1; b < 4; ++b) {
      const BodyState s = world.body_state(b);
      out.insert(out.end(), s.position.data(), s.position.data() + 3);
    }
    for (int j = 0; j < 2; ++j) out.push_back(world.joint_motor_torque(j));  // the motor's share, not the pair's
  }
  return out;
}

TEST(OdeWorldTest, CombinedMotorRowsFollowTheTwoRowSolution) {
  const auto model = Compile(Chain());
  PhysicsParameters two_rows;
  two_rows.combine_motor_rows = false;
  auto reference = MakeOdeWorld(model);
  auto combined = MakeOdeWorld(model);
  const std::vector<double> expected = BrakedTrajectory(*reference, 400, two_rows);
  const std::vector<double> actual = BrakedTrajectory(*combined, 400, {});
  ASSERT_EQ(actual.size(), expected.size());
  for (size_t k = 0; k < actual.size(); ++k) ASSERT_NEAR(actual[k], expected[k], 1e-9) << "coordinate " << k;
}

TEST(OdeWorldTest, CombinedMotorRowsReportTheMotorsShareOfAHoldingTorque) {
  // A motor commanded to rate 0 and a brake, both strong enough, hold the pendulum horizontal. Two rows on one
  // axis with the same target share the load in inverse proportion to their CFM (equal here): the motor reports
  // half of it, whether the step solved the pair as two rows or as one.
  const auto model = Compile(Pendulum(false, true));
  const double gravity_torque = 0.1 * kG * 0.2;
  std::vector<double> torques[2];
  for (int variant = 0; variant < 2; ++variant) {
    PhysicsParameters parameters;
    parameters.combine_motor_rows = variant == 1;
    auto world = MakeOdeWorld(model);
    for (int i = 0; i < 100; ++i) {
      world->SetJointMotor(0, 0.0, 1.0);
      world->SetJointFriction(0, 0.5);
      ASSERT_EQ(world->Step(kDt, parameters), StepStatus::kOk);
      torques[variant].push_back(world->joint_motor_torque(0));
    }
  }
  EXPECT_NEAR(torques[1].back(), 0.5 * gravity_torque, 1e-3);
  for (size_t k = 0; k < torques[0].size(); ++k) EXPECT_NEAR(torques[1][k], torques[0][k], 1e-9) << "step " << k;
}

TEST(OdeWorldTest, CombinedMotorRowsKeepAnAddedTorqueWhenTheStepIsRepeated) {
  // A motor holding against a brake, then a torque kick that reverses the joint: the predicted case fails and the
  // step is repeated with both rows, which must see the kick again.
  const auto model = Compile(Pendulum(false, true));
  std::vector<double> rates[2];
  for (int variant = 0; variant < 2; ++variant) {
    PhysicsParameters parameters = ZeroGravity();
    parameters.combine_motor_rows = variant == 1;
    auto world = MakeOdeWorld(model);
    for (int i = 0; i < 40; ++i) {
      world->SetJointMotor(0, 0.5, 0.1);
      world->SetJointFriction(0, 0.002);
      if (i == 20) world->AddJointTorque(0, -1.0);
      ASSERT_EQ(world->Step(kDt, parameters), StepStatus::kOk);
      rates[variant].push_back(world->joint_rate(0));
    }
  }
  EXPECT_LT(rates[1][20], 0.0);  // the kick acted
  for (size_t k = 0; k < rates[0].size(); ++k) EXPECT_NEAR(rates[1][k], rates[0][k], 1e-9) << "step " << k;
}

TEST(OdeWorldTest, MotorWithoutTorqueReportsNoTorque) {
  // A motor holding the pendulum against gravity carries a torque; once its limit drops to 0 it adds no rows to
  // the step and must report 0, not the torque of its last active step.
  auto world = MakeOdeWorld(Compile(Pendulum(false, true)));
  for (int i = 0; i < 20; ++i) {
    world->SetJointMotor(0, 0.0, 10.0);
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
  }
  ASSERT_GT(std::abs(world->joint_motor_torque(0)), 0.01);
  world->SetJointMotor(0, 0.0, 0.0);
  ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
  EXPECT_EQ(world->joint_motor_torque(0), 0.0);
}

TEST(OdeWorldTest, ResetTurnsMotorsAndFrictionOff) {
  auto world = MakeOdeWorld(Compile(Pendulum(false, true)));
  world->SetJointMotor(0, 3.0, 10.0);
  world->SetJointFriction(0, 10.0);
  RunFor(*world, 0.1);
  world->Reset();
  RunFor(*world, 0.2);  // a free pendulum again: gravity swings it
  EXPECT_LT(world->joint_angle(0), -0.1);
}

TEST(OdeWorldTest, CompliantMotorYieldsInProportionToItsTorque) {
  // A compliant motor (SetJointMotorCompliance c) holds against a steady load τ by yielding: once the rate is
  // steady the motor carries the load, λ = −τ, and the joint turns at u = v − c·λ = v + c·τ instead of v. The
  // relation u = v − c·λ holds in every step while the motor is inside its limit. A sliding brake f takes its
  // share first (λ = −(τ − f)), whether the step solves motor and brake as two rows or as one.
  const auto model = Compile(Pendulum(false, true));
  const double compliance = 0.5;  // rad/s per N·m
  const double load = 0.02;       // N·m
  const double brake = 0.005;     // N·m
  const double velocity = 0.1;    // rad/s
  std::vector<double> rates[2];
  for (int variant = 0; variant < 2; ++variant) {
    PhysicsParameters parameters = ZeroGravity();
    parameters.combine_motor_rows = variant == 1;
    auto world = MakeOdeWorld(model);
    world->SetJointMotorCompliance(0, compliance);
    for (int i = 0; i < 100; ++i) {
      world->SetJointMotor(0, velocity, 1.0);
      world->SetJointFriction(0, brake);
      world->AddJointTorque(0, load);
      ASSERT_EQ(world->Step(kDt, parameters), StepStatus::kOk);
      ASSERT_NEAR(world->joint_rate(0), velocity - compliance * world->joint_motor_torque(0), 1e-9) << "step " << i;
      rates[variant].push_back(world->joint_rate(0));
    }
    EXPECT_NEAR(world->joint_motor_torque(0), -(load - brake), 1e-6);
    EXPECT_NEAR(world->joint_rate(0), velocity + compliance * (load - brake), 1e-6);  // 0.1075, not 0.1
  }
  for (size_t k = 0; k < rates[0].size(); ++k) EXPECT_NEAR(rates[1][k], rates[0][k], 1e-9) << "step " << k;
}

TEST(OdeWorldTest, MotorComplianceZeroAndResetRestoreTheStiffMotor) {
  // The stiff default (CFM 1e-5) yields 1e-5 rad/s per N·m: under the same load the rate stays v to 1e-6.
  auto world = MakeOdeWorld(Compile(Pendulum(false, true)));
  const auto run = [&world] {
    for (int i = 0; i < 100; ++i) {
      world->SetJointMotor(0, 0.1, 1.0);
      world->AddJointTorque(0, 0.02);
      EXPECT_EQ(world->Step(kDt, ZeroGravity()), StepStatus::kOk);
    }
    return world->joint_rate(0);
  };
  world->SetJointMotorCompliance(0, 0.5);
  EXPECT_NEAR(run(), 0.11, 1e-6);
  world->SetJointMotorCompliance(0, 0.0);
  EXPECT_NEAR(run(), 0.1, 1e-6);
  world->SetJointMotorCompliance(0, 0.5);
  world->Reset();
  EXPECT_NEAR(run(), 0.1, 1e-6);
}

TEST(OdeWorldTest, AddedBodyInertiaCountsAboutTheHingeAsItsProjection) {
  // The bob turns about its own centre (I = m (lx² + ly²)/12 about z). A torque τ for one step gives the rate
  // τ·dt/(I + J·(a·z)²): inertia J added about the hinge axis counts fully, about a perpendicular axis not at
  // all, about an axis at 45° by half (the hinge removes the coupling of the off-diagonal terms). Reset takes
  // it away.
  PhysicsDescription d = Pendulum(false, false);
  d.bodies[0].position = Eigen::Vector3d::Zero();
  const auto model = Compile(d);
  const double inertia = 0.1 * (0.1 * 0.1 + 0.02 * 0.02) / 12;
  const double added = 2e-4;  // kg·m², about 2.3 I
  const double torque = 1e-3;
  const auto rate_after_kick = [&](PhysicsWorld& world) {
    world.AddJointTorque(0, torque);
    RunFor(world, kDt, ZeroGravity());
    return world.joint_rate(0);
  };
  const auto rate_for = [&](double effective) { return torque * kDt / effective; };
  struct Case {
    Eigen::Vector3d axis;
    double share;  // (a·z)²
  };
  for (const Case& c : {Case{{0, 0, 1}, 1.0}, Case{{0, 0, -2}, 1.0}, Case{{1, 0, 0}, 0.0}, Case{{1, 0, 1}, 0.5}}) {
    auto world = MakeOdeWorld(model);
    world->AddBodyInertia(0, c.axis, added);
    const double expected = rate_for(inertia + c.share * added);
    EXPECT_NEAR(rate_after_kick(*world), expected, 1e-6 * expected) << c.axis.transpose();
  }
  auto world = MakeOdeWorld(model);
  world->AddBodyInertia(0, Eigen::Vector3d::UnitZ(), added);
  world->AddBodyInertia(0, Eigen::Vector3d::UnitZ(), added);  // adds up
  EXPECT_NEAR(rate_after_kick(*world), rate_for(inertia + 2 * added), 1e-6 * rate_for(inertia + 2 * added));
  world->Reset();
  EXPECT_NEAR(rate_after_kick(*world), rate_for(inertia), 1e-6 * rate_for(inertia));
}

TEST(OdeWorldTest, WorldsFromOneModelAreIndependent) {
  const auto model = Compile(Chain());
  auto a = MakeOdeWorld(model);
  auto b = MakeOdeWorld(model);
  const std::vector<double> first = Trajectory(*a, 100);
  EXPECT_EQ(b->body_state(1).position, model->body(1).position);  // untouched by a's steps
  BodyState moved = a->body_state(2);
  moved.position.y() += 1.0;
  a->SetBodyState(2, moved);
  EXPECT_TRUE(Trajectory(*b, 100) == first);
}

TEST(OdeWorldTest, EngineErrorBecomesAStatusUntilReset) {
  auto world = MakeOdeWorld(Compile(BallAboveShelf()));
  // ODE's dWorldStep traps a non-positive step size with its debug handler.
  EXPECT_EQ(world->Step(0.0, {}), StepStatus::kEngineError);
  EXPECT_THAT(world->last_error(), HasSubstr("stepsize must be > 0"));
  EXPECT_EQ(world->Step(kDt, {}), StepStatus::kEngineError);  // sticky
  world->Reset();
  EXPECT_EQ(world->last_error(), "");
  RunFor(*world, 2.0);
  EXPECT_NEAR(world->body_state(2).position.y(), 0.36, 1.5e-3);  // works as new
}

TEST(OdeWorldTest, QuickStepSolverAlsoRestsTheSphere) {
  PhysicsDescription d;
  d.bodies = {Floor(), Sphere("Ball", 0.05, 0.1, "ABS", {0, 0.5, 0})};
  auto world = MakeOdeWorld(Compile(d));
  PhysicsParameters p;
  p.solver = Solver::kQuickStep;
  RunFor(*world, 3.0, p);
  EXPECT_NEAR(world->body_state(1).position.y(), 0.05, 1.5e-3);
}

TEST(OdeWorldTest, QuickStepRunsDoNotDependOnWhatTheProcessSteppedBefore) {
  // dWorldQuickStep shuffles its constraints with ODE's one process-wide random generator.
  PhysicsParameters quick;
  quick.solver = Solver::kQuickStep;
  const auto model = Compile(Chain());
  const auto run = [&] {
    auto world = MakeOdeWorld(model);
    std::vector<double> out;
    for (int i = 0; i < 100; ++i) {
      EXPECT_EQ(world->Step(kDt, quick), StepStatus::kOk);
      const Eigen::Vector3d p = world->body_state(3).position;
      out.insert(out.end(), p.data(), p.data() + 3);
    }
    return out;
  };
  const std::vector<double> first = run();
  EXPECT_TRUE(run() == first);  // exact
}

}  // namespace
}  // namespace orcs::physics
