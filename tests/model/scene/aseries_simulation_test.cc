// The A-Series inside a simulation: the agent's values, the motor and sensor stages in the step, standing.
#include <gtest/gtest.h>

#include <cmath>

#include "model/scene/simulation.h"

namespace orcs::scene {
namespace {

// One A-Series named Humanoid on the floor: what orcs-sim runs without -env, on each engine (/Simulation/Engine).
class ASeriesSimulationTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    EnvironmentDescription environment;
    environment.agents.push_back(AgentDescription{});
    simulation_.LoadEnvironment(environment);
    simulation_.repository().Set("/Simulation/Engine", GetParam());
    simulation_.Build();
    ASSERT_EQ(simulation_.engine(), GetParam());
  }
  double Value(const std::string& path) { return simulation_.repository().Get(path).as_double(); }
  double HeadHeight() { return simulation_.repository().Get("/Sim/Humanoid/Middle/Head/Position").as_vector3().y(); }
  void Run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / 0.01));
    for (int i = 0; i < steps; ++i) ASSERT_EQ(simulation_.Step(), SimulationStatus::kOk) << simulation_.message();
  }
  Simulation simulation_;
};

TEST_P(ASeriesSimulationTest, StandsForTenSecondsWithoutInput) {
  const double start = HeadHeight();
  EXPECT_NEAR(start, 0.4037, 1e-9);  // spec §2a: head centre, lift included
  Run(10.0);
  EXPECT_NEAR(HeadHeight(), start, 0.01);
}

TEST_P(ASeriesSimulationTest, RegistersTheInterfaceValuesOfEveryMotorAndBoard) {
  const VariableRepository& values = simulation_.repository();
  EXPECT_EQ(values.Match("/Sim/Humanoid/.*/DesiredAngle").size(), 21u);
  EXPECT_EQ(values.Match("/Sim/Humanoid/.*/DesiredTorque").size(), 21u);
  EXPECT_EQ(values.Match("/Sim/Humanoid/.*/JointAngle").size(), 21u);
  EXPECT_EQ(values.Match("/Sim/Humanoid/AB../AccelAxis[12]").size(), 16u);
  // The original's per-motor sensor range (spec §4d), which orcs did not publish before issue 22.
  EXPECT_EQ(values.Match("/Sim/Humanoid/.*/MinSensorAngle").size(), 21u);
  EXPECT_DOUBLE_EQ(Value("/Sim/Humanoid/Head/Tilt/MinSensorAngle"), -150.0);
  EXPECT_DOUBLE_EQ(Value("/Sim/Humanoid/Waist/MaxSensorAngle"), 150.0);
  EXPECT_DOUBLE_EQ(Value("/Sim/Humanoid/Right/Knee/DesiredTorque"), 0.586810005);
  EXPECT_DOUBLE_EQ(Value("/AngularMotor/PID/Proportional"), 20.0);
}

TEST_P(ASeriesSimulationTest, AccelerometersReadGravityAtRest) {
  Run(1.0);
  // spec §5 expected readings at rest: ABHR Axis2 = −9.81, ABHL Axis2 = +9.81, ABAR/ABAL Axis1 = −9.81.
  EXPECT_NEAR(Value("/Sim/Humanoid/ABHR/AccelAxis2"), -9.81, 0.05);
  EXPECT_NEAR(Value("/Sim/Humanoid/ABHL/AccelAxis2"), 9.81, 0.05);
  EXPECT_NEAR(Value("/Sim/Humanoid/ABAR/AccelAxis1"), -9.81, 0.05);
  EXPECT_NEAR(Value("/Sim/Humanoid/ABFR/AccelAxis1"), 0.0, 0.05);
}

TEST_P(ASeriesSimulationTest, ADesiredAngleMovesItsJointAtMostAtMaxVelocity) {
  simulation_.repository().Set("/Sim/Humanoid/Right/ShoulderYaw/DesiredAngle", "60");
  Run(0.1);
  // The PID asks for 20·(60° in rad) ≈ 21 rad/s, clipped to MaxVelocity 3.5 rad/s: after 0.1 s at most ~20°.
  EXPECT_NEAR(Value("/Sim/Humanoid/Right/ShoulderYaw/CurrentVelocity"), 3.5, 1e-12);
  const double after_a_tenth = Value("/Sim/Humanoid/Right/ShoulderYaw/JointAngle");
  EXPECT_GT(after_a_tenth, 5.0);
  EXPECT_LT(after_a_tenth, 3.5 * 0.1 * 180.0 / M_PI + 1.0);
  Run(1.5);
  EXPECT_NEAR(Value("/Sim/Humanoid/Right/ShoulderYaw/JointAngle"), 60.0, 2.0);
}

TEST_P(ASeriesSimulationTest, SameSeedSameSensorNoiseDifferentSeedDifferentNoise) {
  const auto trace = [this](std::uint64_t seed) {
    simulation_.Reset(seed);
    std::vector<double> angles;
    for (int i = 0; i < 20; ++i) {
      simulation_.Step();
      angles.push_back(Value("/Sim/Humanoid/Right/Knee/JointAngle"));
    }
    return angles;
  };
  const std::vector<double> first = trace(7);
  EXPECT_EQ(trace(7), first);
  EXPECT_NE(trace(8), first);
}

INSTANTIATE_TEST_SUITE_P(Engines, ASeriesSimulationTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const ::testing::TestParamInfo<std::string>& engine) { return engine.param; });

}  // namespace
}  // namespace orcs::scene
