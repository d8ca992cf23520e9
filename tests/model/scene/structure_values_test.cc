// The robot and the objects as values (issue 48): structure values written after the build apply at the next
// reset, read back from the physics; values that cannot be built are refused; each motor has its own parameters.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "model/core/error.h"
#include "model/core/text.h"
#include "model/physics/material_table.h"
#include "model/scene/simulation.h"
#include "tests/support/input_error_of.h"

namespace orcs::scene {
namespace {

using ::testing::HasSubstr;

// The index of the physics body called `name`, or -1.
int BodyIndex(const Simulation& simulation, const std::string& name) {
  const physics::PhysicsModel& model = simulation.physics().model();
  for (int b = 0; b < model.body_count(); ++b) {
    if (model.body(b).name == name) return b;
  }
  return -1;
}

void RunFor(Simulation& simulation, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / simulation.StepDuration()));
  for (int i = 0; i < steps; ++i) ASSERT_EQ(simulation.Step(), SimulationStatus::kOk) << simulation.message();
}

double Height(const Simulation& simulation, const std::string& object) {
  return simulation.repository().Get("/Sim/" + object + "/Position").as_vector3().y();
}

// A 10-cm cube dropped from 0.5 m onto the floor, on each engine.
class BoxStructureTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    ObjectDescription box;
    box.name = "Box";
    box.position = {0.0, 0.5, 0.0};
    box.dimension = {0.1, 0.1, 0.1};
    box.dynamic = true;
    box.mass = 0.2;
    EnvironmentDescription environment;
    environment.objects.push_back(box);
    simulation_.LoadEnvironment(environment);
    simulation_.repository().Set("/Simulation/Engine", GetParam());
    simulation_.Build();
  }
  Simulation simulation_;
};

TEST_P(BoxStructureTest, ThePublishedPoseIsNoNewStartPoseAndAResetWithNothingWrittenKeepsTheModel) {
  const auto model = simulation_.shared_model();
  RunFor(simulation_, 1.5);
  EXPECT_NEAR(Height(simulation_, "Box"), 0.05, 0.01) << "at rest on the floor";
  simulation_.Reset();
  EXPECT_DOUBLE_EQ(Height(simulation_, "Box"), 0.5) << "back where the environment put it";
  EXPECT_EQ(simulation_.shared_model(), model) << "nothing written: the same compiled model";
}

TEST_P(BoxStructureTest, ASizeAndAStartPositionWrittenWhileRunningApplyAtTheReset) {
  RunFor(simulation_, 0.5);
  simulation_.repository().Set("/Sim/Box/Height", "0.3");
  simulation_.repository().Set("/Sim/Box/Position", "(0, 1, 0)");
  RunFor(simulation_, 1.0);
  EXPECT_NEAR(Height(simulation_, "Box"), 0.05, 0.01) << "the running world keeps its box until the reset";
  simulation_.Reset();
  const int box = BodyIndex(simulation_, "Box");
  ASSERT_GE(box, 0);
  EXPECT_DOUBLE_EQ(simulation_.physics().model().body(box).geoms.front().size.y(), 0.3);
  EXPECT_DOUBLE_EQ(Height(simulation_, "Box"), 1.0) << "the written start position";
  RunFor(simulation_, 1.5);
  EXPECT_NEAR(Height(simulation_, "Box"), 0.15, 0.01) << "the tall box rests on its new half height";
  simulation_.Reset();
  EXPECT_DOUBLE_EQ(Height(simulation_, "Box"), 1.0) << "the written start position stays the start";
}

// Object Properties' "set as initial": the box at rest on the floor is where every later reset starts it.
TEST_P(BoxStructureTest, APoseKeptAsStartIsWhereEveryLaterResetStartsTheObject) {
  RunFor(simulation_, 1.5);
  const double resting = Height(simulation_, "Box");
  ASSERT_NEAR(resting, 0.05, 0.01) << "at rest on the floor";
  simulation_.KeepPoseAsStart("Box");
  simulation_.Reset();
  EXPECT_DOUBLE_EQ(Height(simulation_, "Box"), resting);
  RunFor(simulation_, 0.5);
  simulation_.Reset();
  EXPECT_DOUBLE_EQ(Height(simulation_, "Box"), resting) << "kept, not only for one reset";
  EXPECT_THAT(test_support::InputErrorOf([&] { simulation_.KeepPoseAsStart("Humanoid/Right/Foot"); }),
              HasSubstr("Humanoid/Right/Foot: no object of the environment has this name"));
}

INSTANTIATE_TEST_SUITE_P(Engines, BoxStructureTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const auto& engine) { return engine.param; });

// One A-Series named Humanoid, built on ODE; `hold` welds a body to the world.
void BuildRobot(Simulation& simulation, const std::string& hold = "") {
  EnvironmentDescription environment;
  AgentDescription robot;
  robot.hold_body = hold;
  environment.agents.push_back(robot);
  simulation.LoadEnvironment(environment);
  simulation.Build();
}

TEST(RobotStructureTest, AFootsMassAndASolePadsMaterialApplyAtTheResetAndNotBefore) {
  Simulation simulation;
  BuildRobot(simulation);
  const int foot = BodyIndex(simulation, "Humanoid/Right/Foot");
  ASSERT_GE(foot, 0);
  const double before = simulation.physics().model().total_mass(foot);
  simulation.repository().Set("/Sim/Humanoid/Right/Foot/Mass", "0.5");
  simulation.repository().Set("/Sim/Humanoid/Right/Foot/RightSolePadHeel/Material", "ABS");
  EXPECT_DOUBLE_EQ(simulation.physics().model().total_mass(foot), before);
  simulation.Reset();
  const physics::PhysicsModel& model = simulation.physics().model();
  EXPECT_NEAR(model.total_mass(foot), before - 0.064219 + 0.5, 1e-12);  // the main box's 0.064219 kg replaced
  const physics::BodyDescription& body = model.body(foot);
  std::string heel_material;
  for (const physics::GeomDescription& geom : body.geoms) {
    if (geom.name == "Right sole pad heel") heel_material = geom.material;
  }
  EXPECT_EQ(heel_material, "ABS");
  EXPECT_EQ(simulation.model().morphology(0).bodies[0].mass, 0.5);
}

TEST(RobotStructureTest, ValuesThatCannotBeBuiltAreRefusedWithWhatWouldDo) {
  Simulation simulation;
  BuildRobot(simulation);
  VariableRepository& values = simulation.repository();
  EXPECT_THAT(test_support::InputErrorOf([&] { values.Set("/Sim/Humanoid/Right/Foot/Mass", "0"); }),
              HasSubstr("/Sim/Humanoid/Right/Foot/Mass: expected a number from 1e-06 to 1000, found '0'"));
  EXPECT_THAT(test_support::InputErrorOf([&] { values.Set("/Sim/Humanoid/Right/Tibia/Height", "-0.1"); }),
              HasSubstr("expected a number from 1e-05 to 10"));
  EXPECT_THAT(test_support::InputErrorOf([&] { values.Set("/Sim/Humanoid/Right/Foot/Material", "Jelly"); }),
              HasSubstr("expected one of PlasticsWhite, PlasticsGray, ABS, Latex"));
  // Each stop is fine alone; together they cross: refused at the reset, which keeps the old world.
  const double max = values.Get("/Sim/Humanoid/Right/Knee/MaxAngle").as_double();
  values.Set("/Sim/Humanoid/Right/Knee/MinAngle", std::to_string(max + 1.0));
  EXPECT_THAT(test_support::InputErrorOf([&] { simulation.Reset(); }),
              HasSubstr("/Sim/Humanoid/Right/Knee/MinAngle: expected at most /Sim/Humanoid/Right/Knee/MaxAngle"));
  RunFor(simulation, 0.1);
}

TEST(RobotStructureTest, TheRobotsValuesExistBeforeTheBuildForInitialValueFiles) {
  Simulation simulation;
  EnvironmentDescription environment;
  environment.agents.push_back(AgentDescription{});
  simulation.LoadEnvironment(environment);
  simulation.repository().Set("/Sim/Humanoid/Middle/Head/Mass", "0.1");
  simulation.repository().Set("/Sim/Humanoid/Right/Knee/AngularMotor/PID/Proportional", "12");
  simulation.Build();
  const int head = BodyIndex(simulation, "Humanoid/Middle/Head");
  ASSERT_GE(head, 0);
  EXPECT_DOUBLE_EQ(simulation.physics().model().total_mass(head), 0.1);
  EXPECT_DOUBLE_EQ(simulation.repository().Get("/Sim/Humanoid/Right/Knee/AngularMotor/PID/Proportional").as_double(), 12);
}

struct ElbowErrors {
  double right = 0.0;  ///< |JointAngle − DesiredAngle| of the right elbow, degrees
  double left = 0.0;   ///< the same of the left elbow
};

// From the reset, both elbows of the held robot are asked to turn by 40° for `seconds`.
ElbowErrors ElbowErrorsAfter(Simulation& simulation, double seconds) {
  simulation.Reset();
  VariableRepository& values = simulation.repository();
  values.Set("/Sim/Humanoid/Right/Elbow/DesiredAngle", "40");
  values.Set("/Sim/Humanoid/Left/Elbow/DesiredAngle", "40");
  RunFor(simulation, seconds);
  return {std::abs(values.Get("/Sim/Humanoid/Right/Elbow/JointAngle").as_double() - 40.0),
          std::abs(values.Get("/Sim/Humanoid/Left/Elbow/JointAngle").as_double() - 40.0)};
}

TEST(PerMotorParameterTest, AMotorsOwnGainFollowsTheGlobalUntilWrittenAndThenThatJointTracksWorse) {
  Simulation simulation;
  BuildRobot(simulation, "Middle/UpperBody");
  VariableRepository& values = simulation.repository();
  const std::string right = "/Sim/Humanoid/Right/Elbow/AngularMotor/PID/Proportional";
  const std::string left = "/Sim/Humanoid/Left/Elbow/AngularMotor/PID/Proportional";
  EXPECT_EQ(values.Match("/Sim/Humanoid/.*/AngularMotor/PID/Proportional").size(), 21u);
  values.Set("/AngularMotor/PID/Proportional", "25");
  EXPECT_DOUBLE_EQ(values.Get(right).as_double(), 25.0) << "follows the global";
  const ElbowErrors alike = ElbowErrorsAfter(simulation, 0.15);
  EXPECT_NEAR(alike.right, alike.left, 0.25 * alike.left + 0.5) << "the same gain: mirror images";

  values.Set(right, "1");
  values.Set("/AngularMotor/PID/Proportional", "30");
  EXPECT_DOUBLE_EQ(values.Get(right).as_double(), 1.0) << "written: keeps its own";
  EXPECT_DOUBLE_EQ(values.Get(left).as_double(), 30.0) << "not written: still follows";
  const ElbowErrors weak_right = ElbowErrorsAfter(simulation, 0.15);
  EXPECT_GT(weak_right.right, 2.0 * weak_right.left) << "right " << weak_right.right << "°, left " << weak_right.left << "°";
  EXPECT_GT(weak_right.right, alike.right);
}

// The physical servo model's values are per motor too: the right elbow's own torque constant a tenth of the
// others' makes it track worse than the left, while the global switch /Servo/Enabled runs the model for all.
TEST(PerMotorParameterTest, AMotorsOwnServoTorqueConstantMakesThatJointTrackWorse) {
  Simulation simulation;
  BuildRobot(simulation, "Middle/UpperBody");
  VariableRepository& values = simulation.repository();
  values.Set("/Servo/Enabled", "T");
  const std::string right = "/Sim/Humanoid/Right/Elbow/Servo/TorqueConstant";
  EXPECT_EQ(values.Find("/Sim/Humanoid/Right/Elbow/Servo/Enabled"), nullptr) << "one switch for every motor";
  const ElbowErrors alike = ElbowErrorsAfter(simulation, 0.15);
  EXPECT_NEAR(alike.right, alike.left, 0.25 * alike.left + 0.5) << "the same servos: mirror images";
  values.Set(right, text::FormatDouble(values.Get("/Servo/TorqueConstant").as_double() / 10.0));
  const ElbowErrors weak_right = ElbowErrorsAfter(simulation, 0.15);
  EXPECT_GT(weak_right.right, 2.0 * weak_right.left) << "right " << weak_right.right << "°, left " << weak_right.left << "°";
}

// Each accelerometer board has its own copies of the /AccelSensor/... values: ABFR's own output range of 0 holds
// its readings at 0, the other boards read on; a write of the global reaches the boards that kept theirs.
TEST(PerBoardParameterTest, ABoardsOwnRangeBoundsItsReadingsAndNotTheOthers) {
  Simulation simulation;
  BuildRobot(simulation, "Middle/UpperBody");
  VariableRepository& values = simulation.repository();
  EXPECT_EQ(values.Match("/Sim/Humanoid/[^/]+/AccelSensor/Range").size(), 8u) << "one copy per board";
  values.Set("/Sim/Humanoid/ABFR/AccelSensor/Range", "0");
  values.Set("/AccelSensor/Range", "20");
  EXPECT_DOUBLE_EQ(values.Get("/Sim/Humanoid/ABFL/AccelSensor/Range").as_double(), 20.0) << "follows the global";
  EXPECT_DOUBLE_EQ(values.Get("/Sim/Humanoid/ABFR/AccelSensor/Range").as_double(), 0.0) << "keeps its own";
  simulation.Reset();
  RunFor(simulation, 0.1);
  double others = 0.0;
  for (const char* board : {"ABFL", "ABHR", "ABHL"}) {
    others += std::abs(values.Get(std::string("/Sim/Humanoid/") + board + "/AccelAxis1").as_double()) +
              std::abs(values.Get(std::string("/Sim/Humanoid/") + board + "/AccelAxis2").as_double());
  }
  EXPECT_EQ(values.Get("/Sim/Humanoid/ABFR/AccelAxis1").as_double(), 0.0);
  EXPECT_EQ(values.Get("/Sim/Humanoid/ABFR/AccelAxis2").as_double(), 0.0);
  EXPECT_GT(others, 0.0) << "the other boards read on (noise and gravity at least)";
}

// The physics joint called `name`, or null.
const physics::JointDescription* JointNamed(const Simulation& simulation, const std::string& name) {
  const physics::PhysicsModel& model = simulation.physics().model();
  for (int j = 0; j < model.joint_count(); ++j) {
    if (model.joint(j).name == name) return &model.joint(j);
  }
  return nullptr;
}

// A board's placement and material and a hinge's axis points are structure values too: written, they apply at
// the reset; an axis of two equal points is refused there, naming the value.
TEST(RobotStructureTest, ABoardsPlacementAndAHingesAxisApplyAtTheReset) {
  Simulation simulation;
  BuildRobot(simulation, "Middle/UpperBody");
  VariableRepository& values = simulation.repository();
  const int foot = BodyIndex(simulation, "Humanoid/Right/Foot");
  ASSERT_GE(foot, 0);
  const auto board = [&]() -> const physics::GeomDescription& {
    for (const physics::GeomDescription& geom : simulation.physics().model().body(foot).geoms) {
      if (geom.name == "ABFR") return geom;
    }
    throw std::logic_error("no ABFR geom on the right foot");
  };
  const Eigen::Vector3d placed = board().offset;
  const Eigen::Vector3d moved = values.Get("/Sim/Humanoid/ABFR/Position").as_vector3() + Eigen::Vector3d(0.01, 0, 0);
  values.Set("/Sim/Humanoid/ABFR/Position", Value(moved).ToString());
  values.Set("/Sim/Humanoid/ABFR/Material", "Latex");
  const Eigen::Vector3d axis = JointNamed(simulation, "Humanoid/Right/Knee")->axis;
  const Eigen::Vector3d p1 = values.Get("/Sim/Humanoid/Right/Knee/AxisPoint1").as_vector3();
  values.Set("/Sim/Humanoid/Right/Knee/AxisPoint2", Value(Eigen::Vector3d(p1 + Eigen::Vector3d(0, 0.1, 0))).ToString());
  EXPECT_EQ(board().offset, placed) << "not before the reset";
  simulation.Reset();
  EXPECT_NEAR((board().offset - placed).x(), 0.01, 1e-12);
  EXPECT_EQ(board().material, "Latex");
  const Eigen::Vector3d tilted = JointNamed(simulation, "Humanoid/Right/Knee")->axis.normalized();
  EXPECT_GT((tilted - axis.normalized()).norm(), 0.5) << "the knee turns about the vertical now";
  EXPECT_NEAR(std::abs(tilted.y()), 1.0, 1e-9);

  values.Set("/Sim/Humanoid/Right/Knee/AxisPoint2", Value(p1).ToString());
  EXPECT_THAT(test_support::InputErrorOf([&] { simulation.Reset(); }),
              HasSubstr("/Sim/Humanoid/Right/Knee/AxisPoint2: expected a point other than /Sim/Humanoid/Right/Knee/AxisPoint1"));
}

// A board turned on its host senses along its turned axes: the sensor model, not only the physics, takes the
// new placement at the reset. ABSR sits on the held upper body, at rest: it reads gravity's projections.
TEST(RobotStructureTest, ABoardTurnedOnItsHostReadsAlongItsNewAxesAfterTheReset) {
  Simulation simulation;
  BuildRobot(simulation, "Middle/UpperBody");
  VariableRepository& values = simulation.repository();
  const auto reading = [&] {
    RunFor(simulation, 0.1);
    return Eigen::Vector2d(values.Get("/Sim/Humanoid/ABSR/AccelAxis1").as_double(),
                           values.Get("/Sim/Humanoid/ABSR/AccelAxis2").as_double());
  };
  simulation.Reset();
  const Eigen::Vector2d before = reading();
  const Eigen::Vector3d rotation = values.Get("/Sim/Humanoid/ABSR/Rotation").as_vector3();
  values.Set("/Sim/Humanoid/ABSR/Rotation", Value(Eigen::Vector3d(rotation + Eigen::Vector3d(90, 0, 0))).ToString());
  simulation.Reset();
  const Eigen::Vector2d after = reading();
  EXPECT_GT((after - before).norm(), 1.0) << "before (" << before.transpose() << "), after (" << after.transpose() << ")";
}

// A body's own inertia replaces the mass rule on either engine: the right lower arm given an inertia far above its
// rule's inertia makes the right elbow track slower than the left. One that no rigid body has is refused.
TEST(RobotStructureTest, ABodysOwnInertiaReplacesTheMassRuleOnEitherEngine) {
  for (const char* engine : {"ODE", "MuJoCo"}) {
    SCOPED_TRACE(engine);
    Simulation simulation;
    BuildRobot(simulation, "Middle/UpperBody");
    VariableRepository& values = simulation.repository();
    values.Set("/Simulation/Engine", engine);
    const std::string inertia = "/Sim/Humanoid/Right/LowerArm/Inertia";
    EXPECT_EQ(values.Get(inertia).as_vector3(), Eigen::Vector3d::Zero()) << "zero: the mass rule";
    const ElbowErrors alike = ElbowErrorsAfter(simulation, 0.15);
    EXPECT_NEAR(alike.right, alike.left, 0.25 * alike.left + 0.5) << "the same arms: mirror images";
    values.Set(inertia, "(0.05, 0.05, 0.05)");
    const ElbowErrors heavy_right = ElbowErrorsAfter(simulation, 0.15);
    const int arm = BodyIndex(simulation, "Humanoid/Right/LowerArm");
    ASSERT_GE(arm, 0);
    EXPECT_EQ(simulation.physics().model().body(arm).inertia, Eigen::Vector3d::Constant(0.05));
    EXPECT_GT(heavy_right.right, 1.5 * heavy_right.left) << "right " << heavy_right.right << "°, left " << heavy_right.left << "°";
    values.Set(inertia, "(1, 0.1, 0.1)");
    EXPECT_THAT(test_support::InputErrorOf([&] { simulation.Reset(); }),
                HasSubstr(inertia + ": expected all zero (the mass rule), or three positive moments"));
  }
}

}  // namespace
}  // namespace orcs::scene
