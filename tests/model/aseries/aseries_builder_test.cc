#include "model/aseries/aseries_builder.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "model/core/error.h"
#include "model/physics/ode/ode_world.h"
#include "model/physics/physics_model.h"

namespace orcs::aseries {
namespace {

using ::testing::HasSubstr;
using physics::BodyDescription;
using physics::Contact;
using physics::GeomDescription;
using physics::PhysicsDescription;
using physics::PhysicsModel;
using physics::PhysicsWorld;
using physics::StepStatus;

constexpr double kDt = 0.01;
constexpr double kPi = std::numbers::pi;
constexpr double kHoldTorque = 1.048;  // N·m, FMaxFactor × 1 of the original (spec §6c)

BodyDescription Floor() {
  BodyDescription floor;
  floor.name = "Floor";
  floor.dynamic = false;
  GeomDescription plane;
  plane.shape = physics::Shape::kPlane;
  plane.material = "PVC";
  floor.geoms.push_back(plane);
  return floor;
}

struct Built {
  PhysicsDescription description;
  ASeriesLayout layout;
};

Built BuildOne(const ASeriesPlacement& placement = {}, bool with_floor = false) {
  Built built;
  if (with_floor) built.description.bodies.push_back(Floor());
  built.layout = AddASeries(DefaultASeriesMorphology(), placement, built.description);
  return built;
}

// World axis-aligned bounds of a box geom of `body`.
std::pair<Eigen::Vector3d, Eigen::Vector3d> Bounds(const BodyDescription& body, const GeomDescription& geom) {
  const Eigen::Matrix3d rotation = (body.orientation * geom.rotation).toRotationMatrix();
  const Eigen::Vector3d centre = body.position + body.orientation * geom.offset;
  const Eigen::Vector3d half = 0.5 * rotation.cwiseAbs() * geom.size;
  return {centre - half, centre + half};
}

void HoldAllMotors(PhysicsWorld& world, const ASeriesLayout& layout) {
  for (int joint : layout.motors) {
    world.SetJointMotor(joint, 0.0, kHoldTorque);  // velocity 0 = hold the pose
    world.SetJointFriction(joint, 0.001);          // static friction fs of the original's Set A
  }
}

const std::vector<std::string>& MotorNames() {
  static const std::vector<std::string> names = {
      "Waist",          "Right/ShoulderYaw", "Left/ShoulderYaw", "Right/ShoulderPitch", "Left/ShoulderPitch",
      "Right/Elbow",    "Left/Elbow",        "Right/HipRoll",    "Left/HipRoll",        "Right/HipPitch",
      "Left/HipPitch",  "Right/HipYaw",      "Left/HipYaw",      "Right/Knee",          "Left/Knee",
      "Right/AnkleYaw", "Left/AnkleYaw",     "Right/AnklePitch", "Left/AnklePitch",     "Head/Pan",
      "Head/Tilt"};
  return names;
}

TEST(ASeriesBuilderTest, AddsBodiesJointsAndExclusionsWithAgentNames) {
  const Built built = BuildOne();
  const PhysicsDescription& d = built.description;
  ASSERT_EQ(d.bodies.size(), 24u);
  ASSERT_EQ(d.joints.size(), 23u);
  EXPECT_EQ(d.bodies[0].name, "Humanoid/Right/Foot");
  EXPECT_EQ(d.bodies[23].name, "Humanoid/Left/LowerArm");
  for (const BodyDescription& body : d.bodies) {
    EXPECT_TRUE(body.dynamic);
    EXPECT_EQ(body.geoms[0].shape, physics::Shape::kBox);
    EXPECT_EQ(body.geoms[0].name, "");
    // Only the pelvis main box is penetrable; its extra geoms collide (§3a).
    for (std::size_t g = 0; g < body.geoms.size(); ++g) {
      EXPECT_EQ(body.geoms[g].collides, !(g == 0 && body.name == "Humanoid/Middle/InvisiblePart"))
          << body.name << " geom " << g;
    }
  }
  EXPECT_EQ(d.bodies[0].geoms.size(), 5u);   // foot: box, 3 pads, board
  EXPECT_EQ(d.bodies[12].geoms.size(), 6u);  // pelvis: box + 5
  EXPECT_EQ(d.bodies[14].geoms.size(), 3u);  // upper body: box + ABSR + ABML
  EXPECT_EQ(d.bodies[0].geoms[4].name, "ABFR");

  EXPECT_EQ(built.layout.agent_name, "Humanoid");
  for (int i = 0; i < 24; ++i) EXPECT_EQ(built.layout.bodies[i], i);
  ASSERT_EQ(built.layout.motors.size(), 21u);
  for (std::size_t m = 0; m < 21; ++m) {
    const physics::JointDescription& joint = d.joints[built.layout.motors[m]];
    EXPECT_EQ(joint.name, "Humanoid/" + MotorNames()[m]);
    EXPECT_EQ(joint.type, physics::JointType::kHinge);
    EXPECT_TRUE(joint.limited);
    EXPECT_TRUE(joint.motorised);
  }
  ASSERT_EQ(built.layout.fixed_joints.size(), 2u);
  const physics::JointDescription& pda = d.joints[built.layout.fixed_joints[0]];
  EXPECT_EQ(pda.name, "Humanoid/Middle/PDAConnector");
  EXPECT_EQ(pda.type, physics::JointType::kFixed);
  EXPECT_EQ(pda.body1, "Humanoid/Middle/InvisiblePart");
  EXPECT_EQ(pda.body2, "Humanoid/Middle/PDA");
  EXPECT_EQ(d.joints[built.layout.fixed_joints[1]].name, "Humanoid/Middle/NeckConnector");
  // 24 entries minus the two board × PDA ones, which a body-pair list cannot express.
  EXPECT_EQ(d.contact_exclusions.size(), 22u);
}

TEST(ASeriesBuilderTest, HingeRangesAreTheSpecsInRadians) {
  const Built built = BuildOne();
  struct Range {
    double lo;
    double hi;
  };
  // §4c, "min, max (rad)".
  const std::vector<Range> ranges = {
      {0.000000, 2.617994},  {-2.617994, 2.617994}, {-2.617994, 2.617994}, {-1.858776, 1.649336},
      {-1.649336, 1.858776}, {-1.858776, 1.518436}, {-1.518436, 1.858776}, {-0.785398, 2.617994},
      {-2.617994, 0.785398}, {-1.308997, 0.698132}, {-0.698132, 1.308997}, {-0.261799, 2.617994},
      {-2.617994, 0.261799}, {0.000000, 2.617994},  {-2.617994, 0.000000}, {-1.413717, 0.514872},
      {-0.514872, 1.413717}, {-1.160644, 0.959931}, {-0.959931, 1.160644}, {-2.356194, 2.356194},
      {-1.658063, 2.617994}};
  for (std::size_t m = 0; m < 21; ++m) {
    const physics::JointDescription& joint = built.description.joints[built.layout.motors[m]];
    EXPECT_NEAR(joint.lo, ranges[m].lo, 1e-6) << joint.name;
    EXPECT_NEAR(joint.hi, ranges[m].hi, 1e-6) << joint.name;
  }
  EXPECT_DOUBLE_EQ(built.description.joints[13].hi, 150.0 * kPi / 180.0);
}

TEST(ASeriesBuilderTest, HingesJoinTheSpecsBodiesAboutTheSpecsAxes) {
  const Built built = BuildOne();
  const auto& joints = built.description.joints;
  // Right/Elbow: body 1 LowerArm, body 2 UpperArm, axis (0, -1, 0) (§4c).
  EXPECT_EQ(joints[5].body1, "Humanoid/Right/LowerArm");
  EXPECT_EQ(joints[5].body2, "Humanoid/Right/UpperArm");
  EXPECT_TRUE(joints[5].axis.isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(joints[17].axis.isApprox(Eigen::Vector3d(0, 0, -1)));  // Right/AnklePitch
  EXPECT_TRUE(joints[0].axis.isApprox(Eigen::Vector3d(-1, 0, 0)));   // Waist
  EXPECT_TRUE(joints[12].axis.isApprox(Eigen::Vector3d(1, 0, 0)));   // Left/HipYaw
  for (const auto& joint : joints) {
    if (joint.type == physics::JointType::kHinge) {
      EXPECT_NEAR(joint.axis.norm(), 1.0, 1e-15) << joint.name;
    }
  }
}

// Decision on quirk 1: anchors are lifted with the bodies, so each axis sits where NERD's formulas put it.
TEST(ASeriesBuilderTest, AnchorsAreLiftedWithTheBodies) {
  const Built built = BuildOne();
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  for (std::size_t i = 0; i < m.motors.size(); ++i) {
    const Eigen::Vector3d expected = m.motors[i].axis_point1 + Eigen::Vector3d(0, 0.001, 0);
    EXPECT_LE((built.description.joints[built.layout.motors[i]].anchor - expected).norm(), 1e-15) << m.motors[i].name;
  }
  // §9b heights (unlifted) + 1 mm.
  EXPECT_NEAR(built.description.joints[13].anchor.y(), 0.1165 + 0.001, 1e-12);  // Right/Knee
  EXPECT_NEAR(built.description.joints[20].anchor.y(), 0.4027 + 0.001, 1e-12);  // Head/Tilt
  EXPECT_NEAR(built.description.joints[0].anchor.y(), 0.2539 + 0.001, 1e-12);   // Waist
}

TEST(ASeriesBuilderTest, MassesAreThoseOfSection2b) {
  Built built = BuildOne();
  double boxes = 0.0;
  for (const BodyDescription& body : built.description.bodies) boxes += body.mass;
  EXPECT_NEAR(boxes, 2.0334, 1e-4);

  const PhysicsModel model(built.description);
  // §2b, "ODE body mass (kg)", creation order.
  const std::vector<double> expected = {0.090219, 0.13391,  0.076443, 0.059963, 0.14326,  0.090219,
                                        0.13391,  0.076443, 0.059963, 0.14326,  0.017064, 0.017064,
                                        0.29143,  0.21099,  0.30056,  0.061191, 0.064275, 0.030000,
                                        0.018806, 0.080976, 0.092318, 0.018806, 0.080976, 0.092318};
  double total = 0.0;
  for (int b = 0; b < 24; ++b) {
    EXPECT_NEAR(model.total_mass(b), expected[b], 1e-5) << model.body(b).name;
    total += model.total_mass(b);
  }
  EXPECT_NEAR(total, 2.3844, 2.3844 * 1e-3);
  EXPECT_NEAR(total, 2.38436, 1e-5);
}

// §9c: whole-robot COM with every body's mass at its box centre (NERD's lumped rule, quirk 2).
TEST(ASeriesBuilderTest, CentreOfMassIsThatOfSection9c) {
  const Built built = BuildOne();
  const PhysicsModel model(built.description);
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (int b = 0; b < model.body_count(); ++b) {
    weighted += model.total_mass(b) * model.body(b).position;
    total += model.total_mass(b);
  }
  const Eigen::Vector3d com = weighted / total;
  EXPECT_NEAR(com.x(), 0.0, 1e-12);
  EXPECT_NEAR(com.y(), 0.22178, 1e-5);
  EXPECT_NEAR(com.z(), -0.017097, 1e-6);
}

// §9b/§9c: the pads' bottoms 0.75 mm above the floor, the head top at 0.4248, overall extent.
TEST(ASeriesBuilderTest, ExtentIsThatOfSection9) {
  const Built built = BuildOne();
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  double lowest_non_pad = std::numeric_limits<double>::infinity();
  for (const BodyDescription& body : built.description.bodies) {
    for (const GeomDescription& geom : body.geoms) {
      const auto [lo, hi] = Bounds(body, geom);
      low = low.cwiseMin(lo);
      high = high.cwiseMax(hi);
      if (geom.name.find("sole pad") == std::string::npos) lowest_non_pad = std::min(lowest_non_pad, lo.y());
    }
  }
  EXPECT_NEAR(low.y(), 0.00075, 1e-12);
  EXPECT_NEAR(lowest_non_pad, 0.0020, 1e-12);  // the foot boxes
  EXPECT_NEAR(high.y(), 0.4248, 1e-12);
  EXPECT_NEAR(low.x(), -0.24735, 1e-12);
  EXPECT_NEAR(high.x(), 0.24735, 1e-12);
  EXPECT_NEAR(low.z(), -0.0876, 1e-12);
  EXPECT_NEAR(high.z(), 0.0883, 1e-12);
}

TEST(ASeriesBuilderTest, LayoutDescribesTheBoards) {
  const Built built = BuildOne();
  const ASeriesLayout& layout = built.layout;
  ASSERT_EQ(layout.boards.size(), 8u);
  const std::vector<std::string> hosts = {"Right/Foot", "Right/Femur", "Middle/UpperBody", "Right/LowerArm",
                                          "Left/Foot",  "Left/Femur",  "Middle/UpperBody", "Left/LowerArm"};
  for (std::size_t i = 0; i < 8; ++i) {
    const ASeriesBoardLayout& board = layout.boards[i];
    const BodyDescription& host = built.description.bodies[board.host_body];
    EXPECT_EQ(host.name, "Humanoid/" + hosts[i]);
    const GeomDescription& geom = host.geoms[board.geom_in_body];
    EXPECT_EQ(geom.name, board.name);
    EXPECT_DOUBLE_EQ(geom.mass, 0.011);
    EXPECT_EQ(geom.material, "ABS");
    EXPECT_TRUE(geom.offset.isApprox(board.local_position));
    EXPECT_TRUE(geom.rotation.isApprox(board.local_rotation));
  }
  // §5, "Axis1/Axis2 in host frame".
  EXPECT_EQ(layout.boards[0].name, "ABFR");
  EXPECT_LE((layout.boards[0].axis1 - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LE((layout.boards[0].axis2 - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_LE((layout.boards[5].axis2 - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);  // ABHL
  EXPECT_LE((layout.boards[7].axis1 - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);   // ABAL
  EXPECT_EQ(layout.boards[6].name, "ABML");  // quirk 14: the name stays
}

TEST(ASeriesBuilderTest, PlacementMovesEveryBodyAndAnchor) {
  const Built home = BuildOne();
  ASeriesPlacement placement;
  placement.position = {1.0, 0.5, -2.0};
  placement.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, -0.3).normalized()));
  const Built moved = BuildOne(placement);
  const Eigen::Quaterniond& r = placement.orientation;
  for (std::size_t b = 0; b < home.description.bodies.size(); ++b) {
    const BodyDescription& a = home.description.bodies[b];
    const BodyDescription& c = moved.description.bodies[b];
    EXPECT_LE((c.position - (r * a.position + placement.position)).norm(), 1e-12) << a.name;
    EXPECT_TRUE(c.orientation.isApprox(r)) << a.name;
    ASSERT_EQ(a.geoms.size(), c.geoms.size());
    for (std::size_t g = 0; g < a.geoms.size(); ++g) EXPECT_EQ(a.geoms[g].offset, c.geoms[g].offset);
  }
  for (std::size_t j = 0; j < home.description.joints.size(); ++j) {
    const physics::JointDescription& a = home.description.joints[j];
    const physics::JointDescription& c = moved.description.joints[j];
    if (a.type != physics::JointType::kHinge) continue;  // fixed joints keep the bodies' relative pose
    EXPECT_LE((c.anchor - (r * a.anchor + placement.position)).norm(), 1e-12) << a.name;
    EXPECT_LE((c.axis - r * a.axis).norm(), 1e-12) << a.name;
  }
  EXPECT_NO_THROW(PhysicsModel{moved.description});
}

TEST(ASeriesBuilderTest, TwoRobotsCoexistInOneWorld) {
  PhysicsDescription d;
  d.bodies.push_back(Floor());
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  const ASeriesLayout first = AddASeries(m, {}, d);
  ASeriesPlacement other;
  other.agent_name = "Rival";
  other.position = {0.6, 0.0, 0.0};
  const ASeriesLayout second = AddASeries(m, other, d);
  EXPECT_EQ(first.bodies.front(), 1);
  EXPECT_EQ(second.bodies.front(), 25);
  EXPECT_EQ(second.motors.front(), 23);
  EXPECT_EQ(second.boards[0].host_body, 25);
  EXPECT_EQ(d.bodies[25].name, "Rival/Right/Foot");
  EXPECT_EQ(d.joints[23].name, "Rival/Waist");
  EXPECT_EQ(d.joints[23].body1, "Rival/Middle/InvisiblePart");

  auto model = std::make_shared<const PhysicsModel>(d);
  EXPECT_EQ(model->body_count(), 49);
  EXPECT_EQ(model->joint_count(), 46);
  // Exclusions stay within each robot.
  EXPECT_TRUE(model->contact_excluded(model->FindBody("Rival/Middle/HeadBase"), model->FindBody("Rival/Middle/Head")));
  EXPECT_FALSE(
      model->contact_excluded(model->FindBody("Humanoid/Middle/HeadBase"), model->FindBody("Rival/Middle/Head")));
  auto world = physics::MakeOdeWorld(model);
  HoldAllMotors(*world, first);
  HoldAllMotors(*world, second);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk) << world->last_error();
  for (int b = 1; b < 25; ++b) {
    const double dy = world->body_state(b + 24).position.y() - world->body_state(b).position.y();
    EXPECT_NEAR(dy, 0.0, 1e-6) << model->body(b).name;  // same robot, same floor, same motion
  }
}

TEST(ASeriesBuilderTest, EmptyAgentNameIsRejected) {
  PhysicsDescription d;
  ASeriesPlacement placement;
  placement.agent_name = "";
  EXPECT_THROW(AddASeries(DefaultASeriesMorphology(), placement, d), InputError);
  placement.agent_name = "A";
  placement.orientation = Eigen::Quaterniond(0, 0, 0, 0);
  try {
    AddASeries(DefaultASeriesMorphology(), placement, d);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("orientation"));
  }
}

std::string GeomName(const PhysicsModel& model, int geom) {
  const physics::GeomInfo& info = model.geom(geom);
  const std::string& name = model.body(info.body).geoms[info.index_in_body].name;
  return model.body(info.body).name + (name.empty() ? "" : ":" + name);
}

// The initial pose: no two different bodies' geoms interpenetrate except the pair the spec lists (HeadBase ×
// Head, 23 mm, suppressed); once the robot has dropped its 0.75 mm, the only constraint-making contacts are
// the sole pads on the floor. In particular nothing of the pelvis touches the HipParts (quirk 3).
TEST(ASeriesBuilderTest, InitialPoseTouchesOnlyWhereTheSpecSays) {
  Built built = BuildOne({}, /*with_floor=*/true);
  auto model = std::make_shared<const PhysicsModel>(built.description);
  auto world = physics::MakeOdeWorld(model);
  HoldAllMotors(*world, built.layout);
  const int head_base = model->FindBody("Humanoid/Middle/HeadBase");
  const int head = model->FindBody("Humanoid/Middle/Head");

  // Step 1 collides the initial pose itself.
  ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
  std::set<std::pair<int, int>> touching;
  for (const Contact& c : world->contacts()) touching.insert(std::minmax(c.body1, c.body2));
  EXPECT_EQ(touching, (std::set<std::pair<int, int>>{std::minmax(head_base, head)}));
  for (const Contact& c : world->contacts()) EXPECT_TRUE(c.excluded);

  int pad_contacts = 0;
  for (int step = 2; step <= 10; ++step) {
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk);
    for (const Contact& c : world->contacts()) {
      if (c.excluded) {
        EXPECT_EQ(std::minmax(c.body1, c.body2), std::minmax(head_base, head)) << "step " << step;
        continue;
      }
      const bool floor1 = c.body1 == 0;
      const int robot_geom = floor1 ? c.geom2 : c.geom1;
      EXPECT_TRUE(floor1 || c.body2 == 0) << GeomName(*model, c.geom1) << " x " << GeomName(*model, c.geom2);
      EXPECT_THAT(GeomName(*model, robot_geom), HasSubstr("sole pad")) << "step " << step;
      ++pad_contacts;
    }
  }
  EXPECT_GT(pad_contacts, 0);  // it did land
}

// With every motor holding its angle the morphology stands: the head stays within 1 cm of its height for 10 s,
// and no two robot bodies make a contact constraint on the way (the unsuppressed hip pairs stay apart).
TEST(ASeriesBuilderTest, StandsWhenEveryMotorHolds) {
  Built built = BuildOne({}, /*with_floor=*/true);
  auto model = std::make_shared<const PhysicsModel>(built.description);
  auto world = physics::MakeOdeWorld(model);
  HoldAllMotors(*world, built.layout);
  const int head = model->FindBody("Humanoid/Middle/Head");
  const Eigen::Vector3d start = world->body_state(head).position;
  int robot_robot_contacts = 0;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(world->Step(kDt, {}), StepStatus::kOk) << "step " << i << ": " << world->last_error();
    for (const Contact& c : world->contacts()) {
      if (!c.excluded && c.body1 != 0 && c.body2 != 0) ++robot_robot_contacts;
    }
  }
  const Eigen::Vector3d end = world->body_state(head).position;
  EXPECT_NEAR(end.y(), start.y(), 0.01);
  EXPECT_NEAR(end.x(), start.x(), 0.01);
  EXPECT_NEAR(end.z(), start.z(), 0.01);
  EXPECT_EQ(robot_robot_contacts, 0);
  for (int joint : built.layout.motors) EXPECT_NEAR(world->joint_angle(joint), 0.0, 0.02) << model->joint(joint).name;
}

}  // namespace
}  // namespace orcs::aseries
