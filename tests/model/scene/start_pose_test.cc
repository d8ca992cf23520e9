// Start-pose randomisation of the initial motor angles: drawing them (parameter_sets.h) and posing the joints
// (agent_posing.h, Simulation::SetAgentJointAngles).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "model/core/rotation.h"
#include "model/scene/agent_posing.h"
#include "model/scene/environment_reader.h"
#include "model/scene/parameter_sets.h"
#include "model/scene/simulation.h"

namespace orcs::scene {
namespace {

// A simulation of one agent given as XML ("" = one free A-Series "Humanoid" on the floor), built and reset.
class StartPoseTest : public ::testing::Test {
 protected:
  void Load(const std::string& agent_xml = "") {
    EnvironmentDescription environment;
    if (agent_xml.empty()) {
      environment.agents.push_back(AgentDescription{});
    } else {
      environment = EnvironmentReader::ReadString("<ORCS version=\"1.0\" defaultRobot=\"false\"><Agent>" + agent_xml +
                                                      "</Agent></ORCS>",
                                                  "agent.xml");
    }
    simulation_.LoadEnvironment(environment);
    simulation_.Build();
    simulation_.Reset(3);
  }
  const physics::PhysicsModel& Physics() const { return *simulation_.model().physics(); }
  const aseries::ASeriesLayout& Layout() const { return simulation_.model().agents()[0]; }
  const std::vector<aseries::MorphologyMotor>& Motors() const { return simulation_.model().morphology(0).motors; }
  physics::BodyState Body(const std::string& name) const {
    const int body = Physics().FindBody(name);
    EXPECT_GE(body, 0) << name;
    return simulation_.physics().body_state(body);
  }
  std::vector<ParameterSet> Draw(double amplitude, int sets, std::uint64_t seed) {
    Randomisation randomisation;
    randomisation.sets = sets;
    randomisation.start_pose.motor_angle_degrees = amplitude;
    return DrawParameterSets(randomisation, seed, simulation_.repository(), Motors(), "s.json");
  }
  // Distinct angles of both signs, up to ±40°, clamped to each motor's range: nested limbs all turn at once.
  std::vector<double> ManyAngles() const {
    std::vector<double> angles;
    for (std::size_t m = 0; m < Motors().size(); ++m) {
      const double angle = (m % 2 == 0 ? 1.0 : -1.0) * (12.0 + 1.3 * static_cast<double>(m));
      angles.push_back(std::clamp(angle, Motors()[m].min_degrees, Motors()[m].max_degrees));
    }
    return angles;
  }
  // Every motor's hinge angle equals the request, and its JointAngle value too (set without noise at the pose).
  void ExpectJointAngles(const std::vector<double>& degrees) {
    const std::string prefix = "/Sim/" + Layout().agent_name + "/";
    for (std::size_t m = 0; m < degrees.size(); ++m) {
      EXPECT_NEAR(simulation_.physics().joint_angle(Layout().motors[m]), DegreesToRadians(degrees[m]), 1e-9)
          << Motors()[m].name;
      EXPECT_NEAR(simulation_.repository().Get(prefix + Motors()[m].name + "/JointAngle").as_double(), degrees[m],
                  1e-7)
          << Motors()[m].name;
    }
  }
  // Every hinge still holds together: its anchor, carried along with body 1 and with body 2, is one point.
  void ExpectHingesConnected() {
    for (int joint : Layout().motors) {
      const int body1 = Physics().joint_body1(joint);
      const int body2 = Physics().joint_body2(joint);
      const auto carried = [&](int body) {
        if (body < 0) return Physics().joint(joint).anchor;
        PosingJoint hinge;
        hinge.joint = joint;
        hinge.proximal_body = body;
        return HingeLineNow(Physics(), hinge, simulation_.physics().body_state(body)).anchor;
      };
      EXPECT_LT((carried(body1) - carried(body2)).norm(), 1e-12) << Physics().joint(joint).name;
    }
  }
  void Run(double seconds) {
    const long steps = std::lround(seconds / 0.01);
    for (long i = 0; i < steps; ++i) ASSERT_EQ(simulation_.Step(), SimulationStatus::kOk) << simulation_.message();
  }

  Simulation simulation_;
};

TEST_F(StartPoseTest, DrawnAnglesLieWithinTheAmplitudeClampedToEachMotorsRange) {
  Load();
  const double amplitude = 40.0;
  const std::vector<ParameterSet> sets = Draw(amplitude, 50, 7);
  int clamped = 0;
  double lowest = 0.0, highest = 0.0;  // Right/ShoulderYaw, range ±150°: never clamped at ±40°
  const int shoulder = simulation_.model().morphology(0).FindMotor("Right/ShoulderYaw");
  for (const ParameterSet& set : sets) {
    ASSERT_EQ(set.motor_angles_degrees.size(), 21u);
    for (std::size_t m = 0; m < Motors().size(); ++m) {
      const double angle = set.motor_angles_degrees[m];
      EXPECT_GE(angle, std::max(-amplitude, Motors()[m].min_degrees)) << Motors()[m].name;
      EXPECT_LE(angle, std::min(amplitude, Motors()[m].max_degrees)) << Motors()[m].name;
      clamped += angle == Motors()[m].min_degrees || angle == Motors()[m].max_degrees;
    }
    lowest = std::min(lowest, set.motor_angles_degrees[shoulder]);
    highest = std::max(highest, set.motor_angles_degrees[shoulder]);
  }
  // Waist and knees start at one end of their range (0…150, −150…0): about half their draws are clamped.
  EXPECT_GT(clamped, 50);
  EXPECT_LT(lowest, -30.0);  // the draws do spread over ±40°
  EXPECT_GT(highest, 30.0);
}

TEST_F(StartPoseTest, SameSeedSameAnglesOtherSetOrSeedOtherAngles) {
  Load();
  const std::vector<ParameterSet> a = Draw(10.0, 3, 7);
  const std::vector<ParameterSet> b = Draw(10.0, 3, 7);
  const std::vector<ParameterSet> c = Draw(10.0, 3, 8);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k].motor_angles_degrees, b[k].motor_angles_degrees);  // bit for bit
  EXPECT_NE(a[0].motor_angles_degrees, a[1].motor_angles_degrees);
  EXPECT_NE(a[1].motor_angles_degrees, a[2].motor_angles_degrees);
  EXPECT_NE(a[0].motor_angles_degrees, c[0].motor_angles_degrees);
}

TEST_F(StartPoseTest, AnglesAreDrawnLastAndOnlyWhenRandomised) {
  Load();
  Randomisation randomisation;
  randomisation.sets = 4;
  randomisation.parameters.push_back({"/AngularMotor/PID/Proportional", ParameterDistribution::Kind::kUniform, 10,
                                      30, 0, 0, false, ""});
  randomisation.parameter_files = {{"a.val", {}}, {"b.val", {}}};
  randomisation.start_pose.position = {0.1, 0.05, 0.1};
  randomisation.start_pose.yaw_degrees = 20.0;
  const std::vector<ParameterSet> fixed = DrawParameterSets(randomisation, 5, simulation_.repository(), Motors(), "s");
  randomisation.start_pose.motor_angle_degrees = 5.0;
  const std::vector<ParameterSet> posed = DrawParameterSets(randomisation, 5, simulation_.repository(), Motors(), "s");
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(fixed[k].motor_angles_degrees.empty());
    EXPECT_EQ(posed[k].motor_angles_degrees.size(), 21u);
    // Everything drawn before the angles keeps its bits.
    EXPECT_EQ(posed[k].values, fixed[k].values);
    EXPECT_EQ(posed[k].parameter_file, fixed[k].parameter_file);
    EXPECT_EQ(posed[k].position_offset, fixed[k].position_offset);
    EXPECT_EQ(posed[k].yaw_degrees, fixed[k].yaw_degrees);
  }
}

TEST_F(StartPoseTest, PosingOrderRunsFromThePelvisOutwardAndHoldsEveryMotorOnce) {
  Load();
  const int pelvis = Physics().FindBody("Humanoid/Middle/InvisiblePart");
  ASSERT_EQ(PosingRoot(Physics(), Layout(), simulation_.model().morphology(0)), pelvis);
  const std::vector<PosingJoint> order = PosingOrder(Physics(), Layout(), pelvis);
  ASSERT_EQ(order.size(), 21u);
  std::set<int> motors;
  std::set<int> placed{pelvis, Physics().FindBody("Humanoid/Middle/PDA")};  // bodies whose pose is final
  for (const PosingJoint& hinge : order) {
    motors.insert(hinge.motor);
    EXPECT_EQ(hinge.joint, Layout().motors[hinge.motor]);
    EXPECT_TRUE(placed.count(hinge.proximal_body)) << Physics().joint(hinge.joint).name << " before its parent";
    placed.insert(hinge.distal_bodies.begin(), hinge.distal_bodies.end());
    if (Physics().joint(hinge.joint).name == "Humanoid/Waist") {
      EXPECT_EQ(hinge.sign, -1.0);  // the upper body is the Waist's body 2
      // The whole upper half turns with the waist: upper body, neck, head, both arms.
      EXPECT_EQ(hinge.distal_bodies.size(), 10u);
    }
  }
  EXPECT_EQ(motors.size(), 21u);
}

TEST_F(StartPoseTest, PosingSetsEveryJointAngleAndKeepsThePelvisInPlace) {
  Load();
  const physics::BodyState pelvis = Body("Humanoid/Middle/InvisiblePart");
  const physics::BodyState pda = Body("Humanoid/Middle/PDA");
  const physics::BodyState foot = Body("Humanoid/Right/Foot");
  const std::vector<double> angles = ManyAngles();
  simulation_.SetAgentJointAngles(0, angles);
  ExpectJointAngles(angles);
  ExpectHingesConnected();
  EXPECT_EQ(Body("Humanoid/Middle/InvisiblePart").position, pelvis.position);
  EXPECT_EQ(Body("Humanoid/Middle/InvisiblePart").orientation.coeffs(), pelvis.orientation.coeffs());
  EXPECT_EQ(Body("Humanoid/Middle/PDA").position, pda.position);  // welded to the pelvis
  EXPECT_GT((Body("Humanoid/Right/Foot").position - foot.position).norm(), 0.01);
  EXPECT_EQ(Body("Humanoid/Right/Foot").linear_velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(Body("Humanoid/Right/Foot").angular_velocity, Eigen::Vector3d::Zero());
  // Published: the repository shows the posed foot.
  EXPECT_EQ(simulation_.repository().Get("/Sim/Humanoid/Right/Foot/Position").as_vector3(),
            Body("Humanoid/Right/Foot").position);
}

TEST_F(StartPoseTest, PositiveRightHipYawSwingsTheRightLegForward) {
  Load();
  std::vector<double> angles(Motors().size(), 0.0);
  angles[simulation_.model().morphology(0).FindMotor("Right/HipYaw")] = 30.0;  // spec §4c: forward is +
  const physics::BodyState foot = Body("Humanoid/Right/Foot");
  const physics::BodyState left_foot = Body("Humanoid/Left/Foot");
  simulation_.SetAgentJointAngles(0, angles);
  EXPECT_GT(Body("Humanoid/Right/Foot").position.z() - foot.position.z(), 0.05);  // forward
  EXPECT_GT(Body("Humanoid/Right/Foot").position.y() - foot.position.y(), 0.01);  // and up
  EXPECT_EQ(Body("Humanoid/Left/Foot").position, left_foot.position);
}

TEST_F(StartPoseTest, MovingThePosedAgentKeepsItsJointAngles) {
  Load();
  const std::vector<double> angles = ManyAngles();
  simulation_.SetAgentJointAngles(0, angles);
  simulation_.MoveAgent(0, {0.1, 0.02, -0.05}, 35.0);
  ExpectJointAngles(angles);
  ExpectHingesConnected();
}

TEST_F(StartPoseTest, HeldAgentKeepsItsHeldBodyAndTurnsTheRestAboutIt) {
  Load(R"x(<ASeries name="Held" position="(0,0.1,0)" holdBody="Middle/UpperBody"/>)x");
  ASSERT_EQ(PosingRoot(Physics(), Layout(), simulation_.model().morphology(0)), -1);  // the stand's world
  const physics::BodyState upper = Body("Held/Middle/UpperBody");
  const physics::BodyState pelvis = Body("Held/Middle/InvisiblePart");
  const std::vector<double> angles = ManyAngles();
  simulation_.SetAgentJointAngles(0, angles);
  ExpectJointAngles(angles);
  ExpectHingesConnected();
  EXPECT_EQ(Body("Held/Middle/UpperBody").position, upper.position);
  EXPECT_GT((Body("Held/Middle/InvisiblePart").position - pelvis.position).norm(), 1e-3);  // the waist turned it
  Run(0.2);  // the stand holds the upper body: nothing jumps
  EXPECT_LT((Body("Held/Middle/UpperBody").position - upper.position).norm(), 1e-3);
}

TEST_F(StartPoseTest, PendulumPoleTurnsAboutItsAxis) {
  Load(R"x(<Pendulum position="(0,0.5,0)" poleMass="0.5" poleLength="0.3"/>)x");
  simulation_.SetAgentJointAngles(0, {90.0});
  ExpectJointAngles({90.0});
  // The pole is the hinge's body 1, the world its body 2: +90° about +z turns the hanging pole (−y) to +x.
  EXPECT_NEAR(Body("Pendulum/Pole").position.x(), 0.15, 1e-12);
  EXPECT_NEAR(Body("Pendulum/Pole").position.y(), 0.5, 1e-12);
}

TEST_F(StartPoseTest, PosedStandingRobotWithSmallOffsetsStaysUpright) {
  Load();
  const std::vector<ParameterSet> sets = Draw(3.0, 4, 11);
  for (const ParameterSet& set : sets) {
    simulation_.Reset(static_cast<std::uint64_t>(set.index));
    simulation_.SetAgentJointAngles(0, set.motor_angles_degrees);
    Run(1.0);
    const physics::BodyState head = Body("Humanoid/Middle/Head");
    EXPECT_GT(head.position.y(), 0.35) << "set " << set.index;  // 0.4037 m at the start: still standing
    EXPECT_LT(head.linear_velocity.norm(), 0.5) << "set " << set.index;
  }
}

}  // namespace
}  // namespace orcs::scene
