#include "model/physics/physics_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "model/core/error.h"
#include "model/physics/material_table.h"

namespace orcs::physics {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

GeomDescription Box(double x, double y, double z, const std::string& material) {
  GeomDescription geom;
  geom.shape = Shape::kBox;
  geom.size = {x, y, z};
  geom.material = material;
  return geom;
}

// A floor, two dynamic boxes (A with an extra 0.2 kg geom) and a hinge and a fixed joint between them.
PhysicsDescription ValidDescription() {
  PhysicsDescription d;
  BodyDescription floor;
  floor.name = "Floor";
  floor.dynamic = false;
  GeomDescription plane;
  plane.shape = Shape::kPlane;
  plane.material = "PVC";
  floor.geoms.push_back(plane);
  d.bodies.push_back(floor);

  BodyDescription a;
  a.name = "A";
  a.mass = 0.5;
  a.position = {0, 0.1, 0};
  a.geoms.push_back(Box(0.1, 0.1, 0.1, "abs"));
  GeomDescription pad = Box(0.02, 0.01, 0.02, "Latex");
  pad.name = "pad";
  pad.mass = 0.2;
  pad.offset = {0, -0.05, 0};
  a.geoms.push_back(pad);
  d.bodies.push_back(a);

  BodyDescription b;
  b.name = "B";
  b.mass = 0.25;
  b.position = {0, 0.3, 0};
  b.geoms.push_back(Box(0.1, 0.1, 0.1, "NoSuchMaterial"));
  d.bodies.push_back(b);

  JointDescription hinge;
  hinge.name = "J1";
  hinge.body1 = "B";
  hinge.body2 = "A";
  hinge.anchor = {0, 0.2, 0};
  hinge.axis = {0, 0, 2};
  hinge.limited = true;
  hinge.lo = -0.5;
  hinge.hi = 0.5;
  d.joints.push_back(hinge);

  JointDescription to_world;
  to_world.name = "J2";
  to_world.type = JointType::kFixed;
  to_world.body1 = "A";
  d.joints.push_back(to_world);

  d.contact_exclusions.emplace_back("A", "B");
  return d;
}

// Expects the edit to make the description invalid, with an InputError naming `source` and mentioning every
// one of the `words` (the field, and what was found).
void ExpectInputError(const std::function<void(PhysicsDescription&)>& edit, const std::string& source,
                      const std::vector<std::string>& words) {
  PhysicsDescription d = ValidDescription();
  edit(d);
  try {
    PhysicsModel model(d);
    ADD_FAILURE() << "no InputError for " << source;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), source) << error.what();
    for (const std::string& word : words) EXPECT_THAT(error.what(), HasSubstr(word));
  }
}

TEST(PhysicsModelTest, ValidDescriptionCompiles) { EXPECT_NO_THROW(PhysicsModel{ValidDescription()}); }

TEST(PhysicsModelTest, ResolvesNamesAndGeoms) {
  const PhysicsModel model(ValidDescription());
  EXPECT_EQ(model.body_count(), 3);
  EXPECT_EQ(model.joint_count(), 2);
  EXPECT_EQ(model.geom_count(), 4);
  EXPECT_EQ(model.FindBody("B"), 2);
  EXPECT_EQ(model.FindBody("b"), -1);
  EXPECT_EQ(model.FindJoint("J2"), 1);
  EXPECT_EQ(model.FindJoint("Nope"), -1);

  EXPECT_EQ(model.first_geom(0), 0);
  EXPECT_EQ(model.first_geom(1), 1);
  EXPECT_EQ(model.first_geom(2), 3);
  EXPECT_EQ(model.geom(2).body, 1);
  EXPECT_EQ(model.geom(2).index_in_body, 1);
  EXPECT_EQ(model.geom(0).material, MaterialTable::IndexOf("PVC"));
  EXPECT_EQ(model.geom(1).material, MaterialTable::IndexOf("ABS"));  // "abs", case-insensitive
  EXPECT_EQ(model.geom(2).material, MaterialTable::IndexOf("Latex"));
  EXPECT_EQ(model.geom(3).material, MaterialTable::kUnknown);

  EXPECT_EQ(model.joint_body1(0), 2);
  EXPECT_EQ(model.joint_body2(0), 1);
  EXPECT_EQ(model.joint_body1(1), 1);
  EXPECT_EQ(model.joint_body2(1), -1);  // the static world
}

TEST(PhysicsModelTest, NormalisesAxesAndRotations) {
  PhysicsDescription d = ValidDescription();
  d.bodies[1].orientation = Eigen::Quaterniond(2, 0, 0, 0);
  const PhysicsModel model(d);
  EXPECT_DOUBLE_EQ(model.joint(0).axis.z(), 1.0);
  EXPECT_DOUBLE_EQ(model.body(1).orientation.w(), 1.0);
}

TEST(PhysicsModelTest, TotalMassAddsExtraGeomsButNotTheMainGeomMass) {
  PhysicsDescription d = ValidDescription();
  d.bodies[1].geoms[0].mass = 7.0;  // ignored: the main geom's mass is the body's
  const PhysicsModel model(d);
  EXPECT_DOUBLE_EQ(model.total_mass(0), 0.0);
  EXPECT_DOUBLE_EQ(model.total_mass(1), 0.7);
  EXPECT_DOUBLE_EQ(model.total_mass(2), 0.25);
}

TEST(PhysicsModelTest, ContactExclusionsAreSymmetric) {
  const PhysicsModel model(ValidDescription());
  EXPECT_TRUE(model.contact_excluded(1, 2));
  EXPECT_TRUE(model.contact_excluded(2, 1));
  EXPECT_FALSE(model.contact_excluded(0, 1));
  EXPECT_FALSE(model.contact_excluded(0, 2));
  EXPECT_FALSE(model.contact_excluded(1, 1));
}

TEST(PhysicsModelTest, RejectsDuplicateBodyName) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].name = "A"; }, "body 'A'", {"name", "'A' used twice"});
}

TEST(PhysicsModelTest, RejectsEmptyBodyName) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].name = ""; }, "body #2", {"'name'", "non-empty"});
}

TEST(PhysicsModelTest, RejectsDynamicBodyWithoutPositiveMass) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].mass = 0.0; }, "body 'A'",
                   {"'mass'", "positive", "found 0"});
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].mass = -1.0; }, "body 'B'", {"'mass'", "found -1"});
}

TEST(PhysicsModelTest, StaticBodyNeedsNoMass) {
  PhysicsDescription d = ValidDescription();
  d.bodies[0].mass = 0.0;
  EXPECT_NO_THROW(PhysicsModel{d});
}

TEST(PhysicsModelTest, RejectsDynamicBodyWithoutGeoms) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].geoms.clear(); }, "body 'B'", {"'geoms'", "none"});
}

TEST(PhysicsModelTest, RejectsNonPositiveSizes) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].geoms[0].size.y() = 0.0; }, "body 'A' geom #0",
                   {"'size'", "found (0.1, 0, 0.1)"});
  ExpectInputError(
      [](PhysicsDescription& d) {
        d.bodies[2].geoms[0].shape = Shape::kSphere;
        d.bodies[2].geoms[0].size = {-0.05, 0, 0};
      },
      "body 'B' geom #0", {"'size'", "radius", "found -0.05"});
  ExpectInputError(
      [](PhysicsDescription& d) {
        d.bodies[1].geoms[1].shape = Shape::kCapsule;
        d.bodies[1].geoms[1].size = {0.01, -0.1, 0};
      },
      "body 'A' geom 'pad'", {"'size'", "length", "found -0.1"});
}

TEST(PhysicsModelTest, RejectsPlaneOnDynamicBody) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].geoms[0].shape = Shape::kPlane; }, "body 'B' geom #0",
                   {"'shape'", "static", "dynamic"});
}

TEST(PhysicsModelTest, RejectsDuplicateGeomNameAndNegativeGeomMass) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].geoms[0].name = "pad"; }, "body 'A' geom 'pad'",
                   {"'name'", "used twice"});
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].geoms[1].mass = -0.1; }, "body 'A' geom 'pad'",
                   {"'mass'", "found -0.1"});
}

TEST(PhysicsModelTest, RejectsNonFiniteOrZeroPose) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].position.x() = std::nan(""); }, "body 'A'",
                   {"'position'", "nan"});
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].orientation = Eigen::Quaterniond(0, 0, 0, 0); },
                   "body 'B'", {"'orientation'", "non-zero"});
}

TEST(PhysicsModelTest, RejectsJointWithUnknownBody) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].body1 = "Ghost"; }, "joint 'J1'",
                   {"'body1'", "unknown body 'Ghost'"});
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].body2 = "Ghost"; }, "joint 'J1'",
                   {"'body2'", "unknown body 'Ghost'"});
}

TEST(PhysicsModelTest, RejectsJointWithStaticOrMissingBody) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].body2 = "Floor"; }, "joint 'J1'",
                   {"'body2'", "static body 'Floor'"});
  ExpectInputError([](PhysicsDescription& d) { d.joints[1].body1 = "Floor"; }, "joint 'J2'",
                   {"'body1'", "static body 'Floor'"});
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].body1 = ""; }, "joint 'J1'", {"'body1'", "\"\""});
}

TEST(PhysicsModelTest, RejectsJointBetweenABodyAndItself) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].body2 = "B"; }, "joint 'J1'", {"'body2'", "'B' again"});
}

TEST(PhysicsModelTest, RejectsZeroAxis) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].axis = Eigen::Vector3d::Zero(); }, "joint 'J1'",
                   {"'axis'", "non-zero", "(0, 0, 0)"});
}

TEST(PhysicsModelTest, RejectsLoAboveHi) {
  ExpectInputError(
      [](PhysicsDescription& d) {
        d.joints[0].lo = 0.4;
        d.joints[0].hi = 0.3;
      },
      "joint 'J1'", {"'lo'", "lo <= hi", "found 0.4"});
  // Unlimited hinges ignore the stops.
  PhysicsDescription d = ValidDescription();
  d.joints[0].limited = false;
  d.joints[0].lo = 1.0;
  d.joints[0].hi = -1.0;
  EXPECT_NO_THROW(PhysicsModel{d});
}

TEST(PhysicsModelTest, RejectsStopsBeyondPi) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[0].hi = 4.0; }, "joint 'J1'", {"'hi'", "found 4"});
}

TEST(PhysicsModelTest, RejectsDuplicateJointNameAndMotorisedFixedJoint) {
  ExpectInputError([](PhysicsDescription& d) { d.joints[1].name = "J1"; }, "joint 'J1'", {"'name'", "used twice"});
  ExpectInputError([](PhysicsDescription& d) { d.joints[1].motorised = true; }, "joint 'J2'", {"'motorised'"});
}

TEST(PhysicsModelTest, RejectsExclusionNamingUnknownBody) {
  ExpectInputError([](PhysicsDescription& d) { d.contact_exclusions.emplace_back("A", "Ghost"); },
                   "contact exclusion #1 ('A', 'Ghost')", {"'second'", "unknown body 'Ghost'"});
}

// Sizes and masses ODE cannot integrate (its mass check fails) are rejected here, with the body named,
// instead of failing inside the engine.
TEST(PhysicsModelTest, RejectsSizesAndMassesBeyondWhatOdeIntegrates) {
  ExpectInputError([](PhysicsDescription& d) { d.bodies[2].geoms[0].size.x() = 1e-300; }, "body 'B' geom #0",
                   {"'size'", "from 1e-6 to 1e6 m", "found (1e-300"});
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].geoms[0].size.x() = 1e7; }, "body 'A' geom #0",
                   {"'size'", "from 1e-6 to 1e6 m", "found (1e+07"});
  ExpectInputError([](PhysicsDescription& d) { d.bodies[1].mass = 1e308; }, "body 'A'", {"'mass'", "from 1e-9 to 1e9", "found 1e+308"});
}

}  // namespace
}  // namespace orcs::physics
