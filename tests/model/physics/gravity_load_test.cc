// Gravity's torque on the load of a hinge (model/physics/gravity_load.h), on ODE and MuJoCo: a two-link arm held
// horizontal by its two stiff motors, where each motor's torque must be minus gravity's on what it holds — the
// shoulder both links, the elbow the forearm, which is the elbow's body 2 (the other sense of the angle).
#include "model/physics/gravity_load.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "model/physics/mujoco/mujoco_world.h"
#include "model/physics/ode/ode_world.h"
#include "tests/model/physics/test_worlds.h"

namespace orcs::physics {
namespace {

using namespace test_worlds;  // NOLINT: the shared small worlds

// Upper arm 2 kg centred 0.5 m from the shoulder (at the origin, hinged to the world), forearm 1 kg centred 0.5 m
// beyond the elbow at x = 1 m. The elbow's body 1 is the upper arm: the forearm, its load, is body 2.
PhysicsDescription Arm() {
  PhysicsDescription d;
  d.bodies = {Box("Upper", {0.9, 0.05, 0.05}, 2.0, "ABS", {0.5, 0, 0}),
              Box("Fore", {0.9, 0.05, 0.05}, 1.0, "ABS", {1.5, 0, 0})};
  JointDescription shoulder;
  shoulder.name = "Shoulder";
  shoulder.body1 = "Upper";
  shoulder.axis = {0, 0, 1};
  shoulder.motorised = true;
  JointDescription elbow = shoulder;
  elbow.name = "Elbow";
  elbow.body2 = "Fore";
  elbow.anchor = {1, 0, 0};
  d.joints = {shoulder, elbow};
  d.contact_exclusions = {{"Upper", "Fore"}};
  return d;
}

class GravityLoadTest : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<PhysicsWorld> MakeWorld(std::shared_ptr<const PhysicsModel> model) const {
    return GetParam() == "ODE" ? MakeOdeWorld(std::move(model)) : MakeMujocoWorld(std::move(model));
  }
};

TEST_P(GravityLoadTest, EachHeldMotorsTorqueIsMinusGravitysOnItsLoadInTheAnglesSense) {
  const auto model = std::make_shared<const PhysicsModel>(Arm());
  const std::unique_ptr<PhysicsWorld> world = MakeWorld(model);
  const GravityLoad shoulder(*model, 0, {0, 1});
  const GravityLoad elbow(*model, 1, {1});
  const Eigen::Vector3d gravity(0, -kG, 0);
  // Horizontal: the shoulder carries 2 kg at 0.5 m and 1 kg at 1.5 m, pulling the angle down; the forearm's 1 kg
  // at 0.5 m beyond the elbow turns the forearm down, which raises the elbow's angle (upper arm against forearm).
  EXPECT_NEAR(shoulder.Torque(*world, gravity), -kG * (2.0 * 0.5 + 1.0 * 1.5), 1e-9);
  EXPECT_NEAR(elbow.Torque(*world, gravity), kG * 1.0 * 0.5, 1e-9);
  PhysicsParameters parameters;
  parameters.gravity = gravity;
  for (int i = 0; i < 50; ++i) {
    world->SetJointMotor(0, 0.0, 1000.0);
    world->SetJointMotor(1, 0.0, 1000.0);
    ASSERT_EQ(world->Step(kDt, parameters), StepStatus::kOk);
  }
  EXPECT_NEAR(world->joint_motor_torque(0), -shoulder.Torque(*world, gravity), 0.02 * kG * 2.5);
  EXPECT_NEAR(world->joint_motor_torque(1), -elbow.Torque(*world, gravity), 0.02 * kG * 0.5);
}

TEST_P(GravityLoadTest, FollowsTheLoadAsItTurns) {
  // Swung down freely from horizontal, the shoulder's load torque falls with the cosine of the arm's angle.
  const auto model = std::make_shared<const PhysicsModel>(Arm());
  const std::unique_ptr<PhysicsWorld> world = MakeWorld(model);
  const GravityLoad shoulder(*model, 0, {0, 1});
  const Eigen::Vector3d gravity(0, -kG, 0);
  PhysicsParameters parameters;
  parameters.gravity = gravity;
  for (int i = 0; i < 20; ++i) {
    world->SetJointMotor(1, 0.0, 1000.0);  // the elbow held straight
    ASSERT_EQ(world->Step(kDt, parameters), StepStatus::kOk);
  }
  const double angle = world->joint_angle(0);
  ASSERT_LT(angle, -0.1) << "it fell";
  EXPECT_NEAR(shoulder.Torque(*world, gravity), -kG * 2.5 * std::cos(angle), 0.01 * kG * 2.5);
}

TEST(GravityLoadInputTest, RefusesALoadThatHoldsNeitherBodyOfTheJoint) {
  const PhysicsModel model(Arm());
  EXPECT_THROW(GravityLoad(model, 0, {1}), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Engines, GravityLoadTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const ::testing::TestParamInfo<std::string>& engine) { return engine.param; });

}  // namespace
}  // namespace orcs::physics
