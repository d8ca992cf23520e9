#include "model/aseries/aseries_morphology.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "model/core/error.h"

namespace orcs::aseries {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using Json = nlohmann::json;

std::string ReadSourceFile(const std::string& relative) {
  std::ifstream in(std::string(ORCS_SOURCE_DIR) + "/" + relative, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void ExpectVectorNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tolerance,
                      const std::string& what) {
  EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(), tolerance)
      << what << ": got (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

TEST(ASeriesMorphologyTest, EmbeddedCopyIsTheSourceFile) {
  const std::string on_disk = ReadSourceFile("model/aseries/aseries_morphology.json");
  ASSERT_FALSE(on_disk.empty());
  EXPECT_EQ(DefaultASeriesMorphologyJson(), on_disk);
}

TEST(ASeriesMorphologyTest, HasTheSpecsParts) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  EXPECT_DOUBLE_EQ(m.lift, 0.001);
  EXPECT_EQ(m.bodies.size(), 24u);
  EXPECT_EQ(m.geoms.size(), 15u);
  EXPECT_EQ(m.motors.size(), 21u);
  EXPECT_EQ(m.fixed_joints.size(), 2u);
  EXPECT_EQ(m.contact_exclusions.size(), 24u);
  std::vector<std::string> boards;
  for (const MorphologyBoard& b : m.boards) boards.push_back(b.name);
  EXPECT_THAT(boards, ElementsAre("ABFR", "ABHR", "ABSR", "ABAR", "ABFL", "ABHL", "ABML", "ABAL"));
  // Creation order of §2a.
  std::vector<std::string> bodies;
  for (const MorphologyBody& b : m.bodies) bodies.push_back(b.name);
  EXPECT_THAT(bodies,
              ElementsAre("Right/Foot", "Right/AnkleBox", "Right/Tibia", "Right/Femur", "Right/UpperFemur",
                          "Left/Foot", "Left/AnkleBox", "Left/Tibia", "Left/Femur", "Left/UpperFemur",
                          "Right/HipPart", "Left/HipPart", "Middle/InvisiblePart", "Middle/PDA", "Middle/UpperBody",
                          "Middle/Neck", "Middle/HeadBase", "Middle/Head", "Right/Shoulder", "Right/UpperArm",
                          "Right/LowerArm", "Left/Shoulder", "Left/UpperArm", "Left/LowerArm"));
  // Only the pelvis box is penetrable (§3a).
  for (const MorphologyBody& b : m.bodies) EXPECT_EQ(b.penetrable, b.name == "Middle/InvisiblePart") << b.name;
  // The two board × PDA entries (#4, #5) are narrowed to the board.
  EXPECT_EQ(m.contact_exclusions[3].first_geom, "ABAR");
  EXPECT_EQ(m.contact_exclusions[4].first_geom, "ABAL");
  EXPECT_EQ(m.contact_exclusions[3].second, "Middle/PDA");
}

TEST(ASeriesMorphologyTest, MassesAddUpToSection9a) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  double boxes = 0.0, extras = 0.0, boards = 0.0;
  for (const MorphologyBody& b : m.bodies) boxes += b.mass;
  for (const MorphologyGeom& g : m.geoms) extras += g.mass;
  for (const MorphologyBoard& b : m.boards) boards += b.mass;
  EXPECT_NEAR(boxes, 2.03345, 1e-5);
  EXPECT_NEAR(extras, 0.26291, 1e-5);
  EXPECT_NEAR(boards, 0.088, 1e-12);
  EXPECT_NEAR(boxes + extras + boards, 2.38436, 1e-5);
}

// §2b's inertia column, from the data: a solid box of the main box's size carrying the body's total mass.
TEST(ASeriesMorphologyTest, LumpedInertiaMatchesSection2b) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  struct Expected {
    std::string body;
    double mass;
    Eigen::Vector3d inertia;
  };
  const std::vector<Expected> table = {
      {"Right/Foot", 0.090219, {7.7719e-05, 1.1278e-04, 3.8622e-05}},
      {"Right/Femur", 0.059963, {1.1443e-05, 2.0277e-05, 1.3242e-05}},
      {"Middle/InvisiblePart", 0.29143, {2.0107e-04, 3.7362e-04, 2.8446e-04}},
      {"Middle/PDA", 0.21099, {1.9742e-04, 1.1422e-04, 2.9714e-04}},
      {"Middle/UpperBody", 0.30056, {2.0719e-04, 3.8235e-04, 3.7397e-04}},
      {"Middle/Head", 0.030000, {1.8142e-05, 2.2690e-05, 1.3452e-05}},
      {"Left/LowerArm", 0.092318, {1.8987e-05, 3.5667e-05, 3.2436e-05}},
      {"Right/HipPart", 0.017064, {8.7025e-06, 9.7346e-06, 1.1344e-06}},
  };
  for (const Expected& e : table) {
    const int b = m.FindBody(e.body);
    ASSERT_GE(b, 0) << e.body;
    double total = m.bodies[b].mass;
    for (const MorphologyGeom& g : m.geoms) total += g.host == e.body ? g.mass : 0.0;
    for (const MorphologyBoard& bd : m.boards) total += bd.host == e.body ? bd.mass : 0.0;
    EXPECT_NEAR(total, e.mass, 5e-6) << e.body;  // the spec rounds to 5 significant digits
    const Eigen::Vector3d s = m.bodies[b].size.cwiseProduct(m.bodies[b].size);
    const Eigen::Vector3d inertia = total / 12.0 * Eigen::Vector3d(s.y() + s.z(), s.x() + s.z(), s.x() + s.y());
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(inertia[i] / e.inertia[i], 1.0, 1e-3) << e.body << " axis " << i;
  }
}

// §3a's world-centre column = host centre + local offset.
TEST(ASeriesMorphologyTest, ExtraGeomWorldCentresMatchSection3a) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  const std::vector<Eigen::Vector3d> world = {
      {-0.0202, 0.0087, 0.03855}, {-0.068, 0.0087, 0.02835}, {-0.0435, 0.0087, -0.03925}, {-0.0615, 0.1355, -0.01731},
      {0.0202, 0.0087, 0.03855},  {0.068, 0.0087, 0.02835},  {0.0435, 0.0087, -0.03925},  {0.0615, 0.1355, -0.01731},
      {0, 0.2549, -0.00615},      {-0.0325, 0.2549, -0.04015}, {0.0325, 0.2549, -0.04015}, {0, 0.2324, -0.0315},
      {0, 0.27815, -0.04015},     {-0.21885, 0.3304, -0.0101}, {0.21885, 0.3304, -0.0101}};
  ASSERT_EQ(m.geoms.size(), world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    const MorphologyGeom& g = m.geoms[i];
    const int host = m.FindBody(g.host);
    ASSERT_GE(host, 0) << g.name;
    ExpectVectorNear(m.bodies[host].centre + g.offset, world[i], 1e-9, g.name);
  }
}

// §5: world centres (host centre + local position; every body starts unrotated) and the axes after the local
// rotation, from the NERD Euler angles.
TEST(ASeriesMorphologyTest, BoardsMatchSection5) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  struct Expected {
    std::string name;
    std::string host;
    Eigen::Vector3d world;
    Eigen::Vector3d axis1;
    Eigen::Vector3d axis2;
    Eigen::Vector3d extent;  // axis-aligned size in the host frame
  };
  const std::vector<Expected> table = {
      {"ABFR", "Right/Foot", {-0.0363, 0.02415, 0.03005}, {1, 0, 0}, {0, 0, -1}, {0.0383, 0.0125, 0.026}},
      {"ABHR", "Right/Femur", {-0.07655, 0.1465, -0.01731}, {0, 0, 1}, {0, 1, 0}, {0.0125, 0.026, 0.0383}},
      {"ABSR", "Middle/UpperBody", {-0.03295, 0.35455, -0.0041}, {0, 0, 1}, {1, 0, 0}, {0.026, 0.0125, 0.0383}},
      {"ABAR", "Right/LowerArm", {-0.17035, 0.3304, -0.02385}, {0, 1, 0}, {1, 0, 0}, {0.026, 0.0383, 0.0125}},
      {"ABFL", "Left/Foot", {0.0363, 0.02415, 0.03005}, {-1, 0, 0}, {0, 0, 1}, {0.0383, 0.0125, 0.026}},
      {"ABHL", "Left/Femur", {0.07655, 0.1465, -0.01731}, {0, 0, 1}, {0, -1, 0}, {0.0125, 0.026, 0.0383}},
      {"ABML", "Middle/UpperBody", {0.03295, 0.35455, -0.0041}, {0, 0, 1}, {1, 0, 0}, {0.026, 0.0125, 0.0383}},
      {"ABAL", "Left/LowerArm", {0.17035, 0.3304, -0.02385}, {0, 1, 0}, {1, 0, 0}, {0.026, 0.0383, 0.0125}},
  };
  ASSERT_EQ(m.boards.size(), table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    const MorphologyBoard& b = m.boards[i];
    const Expected& e = table[i];
    EXPECT_EQ(b.name, e.name);
    EXPECT_EQ(b.host, e.host);
    EXPECT_DOUBLE_EQ(b.mass, 0.011);
    EXPECT_EQ(b.material, "ABS");
    ExpectVectorNear(b.size, {0.026, 0.0125, 0.0383}, 0.0, e.name + " size");
    ExpectVectorNear(m.bodies[m.FindBody(b.host)].centre + b.position, e.world, 1e-9, e.name + " centre");
    ExpectVectorNear(b.rotation * b.axis1, e.axis1, 1e-12, e.name + " axis1");
    ExpectVectorNear(b.rotation * b.axis2, e.axis2, 1e-12, e.name + " axis2");
    const Eigen::Vector3d extent = b.rotation.toRotationMatrix().cwiseAbs() * b.size;
    ExpectVectorNear(extent, e.extent, 1e-12, e.name + " extent");
  }
}

TEST(ASeriesMorphologyTest, MotorsAreInMotorOrderWithTheSpecsRanges) {
  const ASeriesMorphology& m = DefaultASeriesMorphology();
  const std::vector<std::string> names = {
      "Waist",          "Right/ShoulderYaw", "Left/ShoulderYaw", "Right/ShoulderPitch", "Left/ShoulderPitch",
      "Right/Elbow",    "Left/Elbow",        "Right/HipRoll",    "Left/HipRoll",        "Right/HipPitch",
      "Left/HipPitch",  "Right/HipYaw",      "Left/HipYaw",      "Right/Knee",          "Left/Knee",
      "Right/AnkleYaw", "Left/AnkleYaw",     "Right/AnklePitch", "Left/AnklePitch",     "Head/Pan",
      "Head/Tilt"};
  ASSERT_EQ(m.motors.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(m.motors[i].name, names[i]) << i;
  // Left/right pairs are mirror images: [a, b] on the right, [-b, -a] on the left (§4c).
  for (std::size_t i = 1; i + 1 < 19; i += 2) {
    EXPECT_DOUBLE_EQ(m.motors[i].min_degrees, -m.motors[i + 1].max_degrees) << names[i];
    EXPECT_DOUBLE_EQ(m.motors[i].max_degrees, -m.motors[i + 1].min_degrees) << names[i];
  }
  const MorphologyMotor& knee = m.motors[13];
  EXPECT_EQ(knee.first_body, "Right/Tibia");
  EXPECT_EQ(knee.second_body, "Right/Femur");
  ExpectVectorNear(knee.axis_point1, {-0.0325, 0.1165, -0.019}, 0.0, "knee anchor (unlifted)");
  EXPECT_DOUBLE_EQ(knee.min_degrees, 0.0);
  EXPECT_DOUBLE_EQ(knee.max_degrees, 150.0);
  EXPECT_DOUBLE_EQ(m.motors[3].min_degrees, -106.5);
  EXPECT_DOUBLE_EQ(m.motors[15].max_degrees, 29.5);
  EXPECT_EQ(m.fixed_joints[0].name, "Middle/PDAConnector");
  EXPECT_EQ(m.fixed_joints[1].second_body, "Middle/Neck");
}

// --- Bad input: every error names the field path. ---

Json DefaultJson() { return Json::parse(std::string(DefaultASeriesMorphologyJson())); }

// Parses `json` after `edit` and returns the InputError's message ("" if none was thrown).
std::string ErrorAfter(const std::function<void(Json&)>& edit) {
  Json json = DefaultJson();
  edit(json);
  try {
    ParseASeriesMorphology(json.dump(2), "robot.json");
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "robot.json");
    return error.what();
  }
  return "";
}

TEST(ASeriesMorphologyTest, TheDefaultJsonParsesAgain) {
  EXPECT_EQ(ErrorAfter([](Json&) {}), "");
}

TEST(ASeriesMorphologyTest, RootBodyIsThePelvisOrTheFirstBodyWhenNotGiven) {
  EXPECT_EQ(DefaultASeriesMorphology().root_body, "Middle/InvisiblePart");  // spec §4a
  Json json = DefaultJson();
  json.erase("root_body");
  EXPECT_EQ(ParseASeriesMorphology(json.dump(), "robot.json").root_body, "Right/Foot");
  EXPECT_THAT(ErrorAfter([](Json& j) { j["root_body"] = "Middle/Tail"; }),
              AllOf(HasSubstr("'root_body'"), HasSubstr("unknown body \"Middle/Tail\"")));
}

TEST(ASeriesMorphologyTest, MissingFieldIsNamed) {
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][3].erase("mass"); }),
              AllOf(HasSubstr("robot.json"), HasSubstr("'bodies[3].mass'"), HasSubstr("missing")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"][20].erase("max_degrees"); }),
              HasSubstr("'motors[20].max_degrees'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j.erase("lift"); }), HasSubstr("'lift'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["boards"][6].erase("axis2"); }), HasSubstr("'boards[6].axis2'"));
}

TEST(ASeriesMorphologyTest, WronglyTypedFieldIsNamed) {
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][0]["mass"] = "heavy"; }),
              AllOf(HasSubstr("'bodies[0].mass'"), HasSubstr("number"), HasSubstr("\"heavy\"")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["geoms"][2]["size"] = Json::array({0.01, 0.02}); }),
              AllOf(HasSubstr("'geoms[2].size'"), HasSubstr("3 numbers")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["geoms"][2]["offset"][1] = "x"; }), HasSubstr("'geoms[2].offset[1]'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][12]["penetrable"] = 1; }),
              HasSubstr("'bodies[12].penetrable'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][1]["color"][3] = 256; }), HasSubstr("'bodies[1].color[3]'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"] = Json::object(); }),
              AllOf(HasSubstr("'motors'"), HasSubstr("an array")));
}

TEST(ASeriesMorphologyTest, BadValuesAreNamed) {
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][5]["size"][0] = 0.0; }),
              AllOf(HasSubstr("'bodies[5].size'"), HasSubstr("positive")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][5]["mass"] = -0.1; }), HasSubstr("'bodies[5].mass'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["geoms"][0]["material"] = "Rubber"; }),
              AllOf(HasSubstr("'geoms[0].material'"), HasSubstr("Rubber")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["geoms"][0]["host"] = "Right/Hoof"; }),
              AllOf(HasSubstr("'geoms[0].host'"), HasSubstr("Right/Hoof")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"][2]["second_body"] = "Middle/UpperBody"; }),
              HasSubstr("'motors[2].second_body'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"][0]["axis_point2"] = j["motors"][0]["axis_point1"]; }),
              HasSubstr("'motors[0].axis_point2'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"][0]["min_degrees"] = 160; }),
              AllOf(HasSubstr("'motors[0].min_degrees'"), HasSubstr("160")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["motors"][1]["max_degrees"] = 190; }), HasSubstr("'motors[1].max_degrees'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["boards"][0]["axis1"] = Json::array({0, 0, 2}); }),
              AllOf(HasSubstr("'boards[0].axis1'"), HasSubstr("unit")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["contact_exclusions"][3]["first_geom"] = "ABAL"; }),
              HasSubstr("'contact_exclusions[3].first_geom'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["version"] = 2; }), HasSubstr("'version'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][3]["inertia"] = Json::array({1.0, 0.1, 0.1}); }),
              AllOf(HasSubstr("'bodies[3].inertia'"), HasSubstr("each at most the sum of the other two")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][3]["inertia"] = Json::array({0.001, -0.001, 0.001}); }),
              HasSubstr("'bodies[3].inertia'"));
}

// A body's own inertia (optional; absent = the mass rule) is read and written back.
TEST(ASeriesMorphologyTest, ABodysOwnInertiaIsReadAndWrittenBack) {
  Json json = DefaultJson();
  json["bodies"][3]["inertia"] = Json::array({0.001, 0.002, 0.0025});
  const ASeriesMorphology parsed = ParseASeriesMorphology(json.dump(), "robot.json");
  EXPECT_EQ(parsed.bodies[3].inertia, Eigen::Vector3d(0.001, 0.002, 0.0025));
  EXPECT_EQ(parsed.bodies[4].inertia, Eigen::Vector3d::Zero()) << "none given: the mass rule";
  const ASeriesMorphology again = ParseASeriesMorphology(WriteASeriesMorphology(parsed), "again.json");
  EXPECT_EQ(again.bodies[3].inertia, parsed.bodies[3].inertia);
  EXPECT_FALSE(Json::parse(WriteASeriesMorphology(parsed))["bodies"][4].contains("inertia"));
}

TEST(ASeriesMorphologyTest, DuplicateNamesAreRejected) {
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][5]["name"] = "Right/Foot"; }),
              AllOf(HasSubstr("'bodies[5]'"), HasSubstr("Right/Foot")));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["boards"][6]["name"] = "ABSR"; }), HasSubstr("'boards[6]'"));
  EXPECT_THAT(ErrorAfter([](Json& j) { j["fixed_joints"][0]["name"] = "Waist"; }),
              HasSubstr("'fixed_joints[0].name'"));
  // A board may not share a name with an extra geom of its host: both become geoms of one body.
  EXPECT_THAT(ErrorAfter([](Json& j) { j["boards"][0]["name"] = "Right sole pad heel"; }),
              HasSubstr("'boards[0].name'"));
}

TEST(ASeriesMorphologyTest, UnknownFieldsAreRejectedButCommentsAreNot) {
  EXPECT_THAT(ErrorAfter([](Json& j) { j["bodies"][2]["masss"] = 0.1; }),
              AllOf(HasSubstr("'bodies[2].masss'"), HasSubstr("no such field")));
  EXPECT_EQ(ErrorAfter([](Json& j) { j["bodies"][2]["comment"] = "the tibia servo"; }), "");
}

TEST(ASeriesMorphologyTest, MalformedJsonNamesTheLine) {
  try {
    ParseASeriesMorphology("{\n  \"format\": \"orcs-aseries-morphology\",\n  \"version\": ,\n}", "bad.json");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "bad.json");
    EXPECT_EQ(error.line(), 3);
    EXPECT_THAT(error.what(), HasSubstr("malformed JSON"));
  }
}

}  // namespace
}  // namespace orcs::aseries
