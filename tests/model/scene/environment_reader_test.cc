#include "model/scene/environment_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <string_view>

#include "model/core/error.h"
#include "tests/support/temp_dir.h"

namespace orcs::scene {
namespace {

using test_support::TempDir;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr const char* kSource = "test.xml";

// Joins lines with '\n', so that the n-th argument is line n of the document.
std::string Lines(std::initializer_list<std::string_view> lines) {
  std::string xml;
  for (std::string_view line : lines) {
    xml += line;
    xml += '\n';
  }
  return xml;
}

// A document whose <Environment> holds a valid object on line 3 and `object` on line 4.
std::string WithObjectOnLine4(std::string_view object) {
  return Lines({R"x(<ORCS version="1.0">)x",
                "  <Environment>",
                R"x(    <object type="box" name="Good" position="(0,0.1,0)" dimension="(0.2,0.2,0.2)"/>)x",
                object,
                "  </Environment>",
                "</ORCS>"});
}

// The InputError reading `xml` throws; fails the test when it throws nothing or something else.
InputError ErrorOf(const std::string& xml) {
  try {
    EnvironmentReader::ReadString(xml, kSource);
  } catch (const InputError& error) {
    return error;
  } catch (const std::exception& error) {
    ADD_FAILURE() << "expected an InputError, got: " << error.what();
    return InputError("(other exception)");
  }
  ADD_FAILURE() << "expected an InputError for:\n" << xml;
  return InputError("(nothing thrown)");
}

// Reading `xml` fails with an error at test.xml:line whose message contains every one of `words`.
void ExpectErrorAt(const std::string& xml, int line, std::initializer_list<std::string_view> words) {
  const InputError error = ErrorOf(xml);
  const std::string what = error.what();
  EXPECT_THAT(what, StartsWith(std::string(kSource) + ":" + std::to_string(line) + ": ")) << xml;
  EXPECT_EQ(error.source(), kSource);
  EXPECT_EQ(error.line(), line) << what;
  for (std::string_view word : words) EXPECT_THAT(what, HasSubstr(std::string(word))) << xml;
  EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
}

std::string ExamplePath() { return std::string(ORCS_SOURCE_DIR) + "/scenarios/environments/example.xml"; }

// ---------------------------------------------------------------------------------------------------------
// Valid input

TEST(EnvironmentReaderTest, ReadsExampleFile) {
  const EnvironmentDescription env = EnvironmentReader::ReadFile(ExamplePath());
  EXPECT_EQ(env.source, ExamplePath());
  EXPECT_EQ(env.floor_material, "PVC");
  ASSERT_EQ(env.objects.size(), 2u);
  ASSERT_EQ(env.agents.size(), 2u);  // the default A-Series and the file's, as in the original

  const ObjectDescription& box = env.objects[0];
  EXPECT_EQ(box.name, "Box");
  EXPECT_EQ(box.type, ObjectType::kBox);
  EXPECT_EQ(box.position, Eigen::Vector3d(0.4, 0.1, 0.4));
  EXPECT_EQ(box.orientation, Eigen::Vector3d(0, 30, 0));
  EXPECT_EQ(box.dimension, Eigen::Vector3d(0.2, 0.2, 0.2));
  EXPECT_EQ(box.material, "Wood");
  EXPECT_EQ(box.color, (Color{139, 69, 19, 255}));  // by (r,g,b); alpha defaults to opaque
  EXPECT_FALSE(box.dynamic);
  EXPECT_EQ(box.mass, 0.0);
  EXPECT_EQ(box.line, 7);

  const ObjectDescription& sphere = env.objects[1];
  EXPECT_EQ(sphere.name, "SecondSphere");
  EXPECT_EQ(sphere.type, ObjectType::kSphere);
  EXPECT_EQ(sphere.position, Eigen::Vector3d(-0.3, 0.5, 0.3));
  EXPECT_EQ(sphere.orientation, Eigen::Vector3d::Zero());
  EXPECT_EQ(sphere.dimension, Eigen::Vector3d(0.05, 0, 0));  // radius first
  EXPECT_EQ(sphere.material, "ABS");
  EXPECT_EQ(sphere.color, (Color{255, 0, 0, 255}));  // by name
  EXPECT_TRUE(sphere.dynamic);
  EXPECT_EQ(sphere.mass, 0.1);
  EXPECT_EQ(sphere.line, 9);

  EXPECT_EQ(env.agents[0].name, "Humanoid");
  EXPECT_EQ(env.agents[0].position, Eigen::Vector3d::Zero());
  const AgentDescription& agent = env.agents[1];
  EXPECT_EQ(agent.type, "ASeries");
  EXPECT_EQ(agent.name, "SecondASeries");
  EXPECT_EQ(agent.position, Eigen::Vector3d(0.5, 0.001, -0.5));
  EXPECT_EQ(agent.orientation, Eigen::Vector3d(0, 90, 0));
  EXPECT_EQ(agent.line, 13);
}

TEST(EnvironmentReaderTest, EmptyFileHasNoObjectsOrAgents) {
  const EnvironmentDescription env =
      EnvironmentReader::ReadFile(std::string(ORCS_SOURCE_DIR) + "/scenarios/environments/empty.xml");
  EXPECT_TRUE(env.objects.empty());
  EXPECT_TRUE(env.agents.empty());
}

TEST(EnvironmentReaderTest, NoXmlMeansOneASeriesAndXmlIsReadAsGiven) {
  const EnvironmentDescription fallback = EnvironmentReader::ReadStringOrDefault("", "job 7");
  EXPECT_EQ(fallback.source, "job 7");
  EXPECT_TRUE(fallback.objects.empty());
  ASSERT_EQ(fallback.agents.size(), 1u);
  EXPECT_EQ(fallback.agents[0].name, AgentDescription{}.name);
  const EnvironmentDescription given = EnvironmentReader::ReadStringOrDefault(
      "<ORCS version=\"1.0\" defaultRobot=\"false\"><Agent><ASeries name=\"Other\"/></Agent></ORCS>", "job 8");
  ASSERT_EQ(given.agents.size(), 1u);
  EXPECT_EQ(given.agents[0].name, "Other");
  EXPECT_THROW(EnvironmentReader::ReadStringOrDefault("<ORCS", "job 9"), InputError);
}

TEST(EnvironmentReaderTest, OptionalAttributesTakeTheirDefaults) {
  const EnvironmentDescription env = EnvironmentReader::ReadString(
      Lines({R"x(<ORCS version="1.0">)x", "<Environment>",
             R"x(<object type="sphere" name="Plain" position="(1,2,3)" dimension="(0.5)"/>)x", "</Environment>",
             "<Agent>", "<ASeries/>", "</Agent>", "</ORCS>"}),
      kSource);
  EXPECT_EQ(env.source, kSource);
  ASSERT_EQ(env.objects.size(), 1u);
  const ObjectDescription& object = env.objects[0];
  EXPECT_EQ(object.position, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(object.orientation, Eigen::Vector3d::Zero());
  EXPECT_EQ(object.material, "Default");
  EXPECT_EQ(object.color, (Color{255, 255, 255, 255}));
  EXPECT_EQ(object.texture, "");
  EXPECT_FALSE(object.dynamic);
  EXPECT_EQ(object.mass, 0.0);
  EXPECT_EQ(object.line, 3);
  ASSERT_EQ(env.agents.size(), 1u);
  EXPECT_EQ(env.agents[0].type, "ASeries");
  EXPECT_EQ(env.agents[0].name, "Humanoid");
  EXPECT_EQ(env.agents[0].position, Eigen::Vector3d::Zero());
  EXPECT_EQ(env.agents[0].orientation, Eigen::Vector3d::Zero());
  EXPECT_EQ(env.agents[0].line, 6);
}

TEST(EnvironmentReaderTest, ReadsColourWithAlphaTextureAndBooleanSpellings) {
  const EnvironmentDescription env = EnvironmentReader::ReadString(
      Lines({R"x(<ORCS version="1.0"><Environment>)x",
             R"x(<object type="box" name="A" position="1 2 3" dimension="(1,1,1)" color="(1,2,3,4)" texture="Wood1" dynamic="T" mass="2"/>)x",
             R"x(<object type="Box" name="B" position="(0,0,0)" dimension="(1,1,1)" dynamic="0" color="BLUE"/>)x",
             R"x(<object type="SPHERE" name="C" position="(0,0,0)" dimension="(1)" dynamic="TRUE" mass="0.5"/>)x",
             "</Environment></ORCS>"}),
      kSource);
  ASSERT_EQ(env.objects.size(), 3u);
  EXPECT_EQ(env.objects[0].position, Eigen::Vector3d(1, 2, 3));  // white space separates too
  EXPECT_EQ(env.objects[0].color, (Color{1, 2, 3, 4}));
  EXPECT_EQ(env.objects[0].texture, "Wood1");
  EXPECT_TRUE(env.objects[0].dynamic);
  EXPECT_EQ(env.objects[0].mass, 2.0);
  EXPECT_EQ(env.objects[1].type, ObjectType::kBox);
  EXPECT_FALSE(env.objects[1].dynamic);
  EXPECT_EQ(env.objects[1].color, (Color{0, 0, 255, 255}));
  EXPECT_EQ(env.objects[2].type, ObjectType::kSphere);
  EXPECT_TRUE(env.objects[2].dynamic);
}

// ---------------------------------------------------------------------------------------------------------
// Bad input: every error names test.xml, the line and the problem.

TEST(EnvironmentReaderTest, MalformedXmlUnclosedTag) {
  // <object ...> on line 4 is never closed; </Environment> on line 5 does not match it.
  ExpectErrorAt(WithObjectOnLine4(R"x(    <object type="box" name="B" position="(0,0,0)" dimension="(1,1,1)">)x"), 4,
                {"malformed XML"});
}

TEST(EnvironmentReaderTest, MalformedXmlUnclosedRoot) {
  ExpectErrorAt(Lines({"<!-- comment -->", R"x(<ORCS version="1.0">)x", "  <Environment>", "  </Environment>"}), 2,
                {"malformed XML"});
}

TEST(EnvironmentReaderTest, MalformedXmlUnquotedAttribute) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type=box name="B" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"malformed XML"});
}

TEST(EnvironmentReaderTest, WrongRootElement) {
  ExpectErrorAt(Lines({R"x(<?xml version="1.0"?>)x", R"x(<Scene version="1.0">)x", "</Scene>"}), 2,
                {"root element", "<ORCS>", "<Scene>"});
}

TEST(EnvironmentReaderTest, NoRootElement) {
  const InputError error = ErrorOf(Lines({R"x(<?xml version="1.0"?>)x", "<!-- nothing here -->"}));
  EXPECT_THAT(error.what(), StartsWith("test.xml"));
  EXPECT_THAT(error.what(), HasSubstr("ORCS"));
}

// Nesting is bounded at 32 levels of elements (docs/formats.md, "Input limits"), with the error at the first element
// past the bound; elements under an <object> are otherwise ignored, so 32 levels read.
std::string NestedUnderObject(int extra_levels, bool shallow_sibling_first) {
  std::string xml = "<ORCS version=\"1.0\">\n<Environment>\n";
  if (shallow_sibling_first) xml += "<object type=\"box\" name=\"A\" position=\"(0,0,0)\" dimension=\"(1,1,1)\"/>\n";
  xml += "<object type=\"box\" name=\"B\" position=\"(0,0,0)\" dimension=\"(1,1,1)\">\n";
  for (int i = 0; i < extra_levels; ++i) xml += "<x>\n";
  for (int i = 0; i < extra_levels; ++i) xml += "</x>";
  return xml + "</object>\n</Environment>\n</ORCS>\n";
}

TEST(EnvironmentReaderTest, ThirtyTwoLevelsOfElementsAreReadAndTheThirtyThirdIsRefusedAtItsLine) {
  EXPECT_EQ(EnvironmentReader::ReadString(NestedUnderObject(29, false), kSource).objects.size(), 1u);
  EXPECT_EQ(EnvironmentReader::ReadString(NestedUnderObject(29, true), kSource).objects.size(), 2u);
  ExpectErrorAt(NestedUnderObject(30, false), 33, {"XML elements nested deeper than 32 levels"});
  ExpectErrorAt(NestedUnderObject(30, true), 34, {"XML elements nested deeper than 32 levels"});
}

// 100,000 levels: tinyxml2 stops parsing long before the stack would overflow; the same one-line error, at the
// line where its own bound stopped it.
TEST(EnvironmentReaderTest, NestingOneHundredThousandDeepIsOneLineError) {
  const InputError error = ErrorOf(NestedUnderObject(100000, false));
  EXPECT_THAT(error.what(), HasSubstr("XML elements nested deeper than 32 levels"));
  EXPECT_EQ(error.source(), kSource);
  EXPECT_GT(error.line(), 33);
  EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
}

TEST(EnvironmentReaderTest, MissingVersion) {
  ExpectErrorAt(Lines({"", "<ORCS>", "</ORCS>"}), 2, {"version", "1.0"});
}

TEST(EnvironmentReaderTest, WrongVersion) {
  ExpectErrorAt(Lines({R"x(<ORCS version="2.0">)x", "</ORCS>"}), 1, {"version", "'2.0'"});
}

TEST(EnvironmentReaderTest, UnknownAttributeOnRoot) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0" units="cm">)x", "</ORCS>"}), 1, {"unknown attribute", "units"});
}

TEST(EnvironmentReaderTest, UnknownElementInOrcs) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "  <Environment>", "  </Environment>", "  <Lights/>", "</ORCS>"}),
                4, {"unknown element", "<Lights>"});
}

TEST(EnvironmentReaderTest, UnknownElementInEnvironment) {
  ExpectErrorAt(WithObjectOnLine4(R"x(    <light position="(0,1,0)"/>)x"), 4, {"unknown element", "<light>"});
}

TEST(EnvironmentReaderTest, UnknownAttributeOnSection) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "", R"x(  <Environment gravity="9.81">)x", "  </Environment>",
                       "</ORCS>"}),
                3, {"unknown attribute", "gravity"});
}

TEST(EnvironmentReaderTest, UnknownAttributeOnObject) {
  ExpectErrorAt(
      WithObjectOnLine4(R"x(<object type="box" name="B" position="(0,0,0)" dimension="(1,1,1)" colour="red"/>)x"), 4,
      {"unknown attribute", "colour", "'B'"});
}

TEST(EnvironmentReaderTest, UnknownObjectType) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="cylinder" name="B" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"type", "cylinder"});
}

// The original named an object without a name after its type; orcs numbers the next ones, names being paths.
TEST(EnvironmentReaderTest, AnObjectWithoutANameIsNamedAfterItsType) {
  const EnvironmentDescription env = EnvironmentReader::ReadString(
      Lines({R"x(<ORCS version="1.0">)x", "<Environment>",
             R"x(<object type="box" position="(0,0.1,0)" dimension="(0.1,0.1,0.1)"/>)x",
             R"x(<object type="sphere" position="(1,0.1,0)" dimension="(0.05)"/>)x",
             R"x(<object type="box" name="box_2" position="(2,0.1,0)" dimension="(0.1,0.1,0.1)"/>)x",
             R"x(<object type="box" position="(3,0.1,0)" dimension="(0.1,0.1,0.1)"/>)x", "</Environment>", "</ORCS>"}),
      kSource);
  ASSERT_EQ(env.objects.size(), 4u);
  EXPECT_EQ(env.objects[0].name, "box");
  EXPECT_EQ(env.objects[1].name, "sphere");
  EXPECT_EQ(env.objects[2].name, "box_2");  // given: kept
  EXPECT_EQ(env.objects[3].name, "box_3");  // box and box_2 taken
}

// The original added the file's robots to its default A-Series (issue 22, item 2); a file that names its own
// Humanoid, holds a rig or says defaultRobot="false" gets none.
TEST(EnvironmentReaderTest, TheDefaultRobotJoinsTheFilesRobotsUnlessTheFileSaysOtherwise) {
  const auto agents = [](const std::string& xml) {
    std::vector<std::string> names;
    for (const AgentDescription& agent : EnvironmentReader::ReadString(xml, kSource).agents) names.push_back(agent.name);
    return names;
  };
  using Names = std::vector<std::string>;
  EXPECT_EQ(agents(R"x(<ORCS version="1.0"/>)x"), Names{"Humanoid"});
  EXPECT_EQ(agents(R"x(<ORCS version="1.0"><Agent><ASeries name="B" position="(1,0,0)"/></Agent></ORCS>)x"),
            (Names{"Humanoid", "B"}));
  EXPECT_EQ(agents(R"x(<ORCS version="1.0"><Agent><ASeries name="Humanoid" position="(1,0,0)"/></Agent></ORCS>)x"),
            Names{"Humanoid"});
  EXPECT_EQ(agents(R"x(<ORCS version="1.0"><Agent><Pendulum/></Agent></ORCS>)x"), Names{"Pendulum"});
  EXPECT_EQ(agents(R"x(<ORCS version="1.0" defaultRobot="true"><Agent><Pendulum position="(1,0.5,0)"/></Agent></ORCS>)x"),
            (Names{"Humanoid", "Pendulum"}));
  EXPECT_EQ(agents(R"x(<ORCS version="1.0" defaultRobot="false"><Agent><ASeries name="B"/></Agent></ORCS>)x"),
            Names{"B"});
  ExpectErrorAt(R"x(<ORCS version="1.0" defaultRobot="maybe"/>)x", 1, {"defaultRobot", "maybe"});
}

TEST(EnvironmentReaderTest, EmptyName) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'name'", "empty"});
}

TEST(EnvironmentReaderTest, NameWithSpaceOrSlash) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="a b" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'name'", "'a b'"});
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="/a" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'name'", "'/a'"});
}

TEST(EnvironmentReaderTest, MissingType) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object name="B" position="(0,0,0)" dimension="(1,1,1)"/>)x"), 4,
                {"missing mandatory attribute 'type'"});
}

TEST(EnvironmentReaderTest, MissingPosition) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" dimension="(1,1,1)"/>)x"), 4,
                {"missing mandatory attribute 'position'"});
}

TEST(EnvironmentReaderTest, MissingDimension) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="sphere" name="B" position="(0,0,0)"/>)x"), 4,
                {"missing mandatory attribute 'dimension'"});
}

TEST(EnvironmentReaderTest, DynamicObjectWithoutMass) {
  ExpectErrorAt(
      WithObjectOnLine4(R"x(<object type="sphere" name="B" position="(0,0,0)" dimension="(1)" dynamic="true"/>)x"), 4,
      {"dynamic", "'mass'"});
}

TEST(EnvironmentReaderTest, NonPositiveMass) {
  for (const char* mass : {"0", "-1", "abc", "inf"}) {
    SCOPED_TRACE(mass);
    ExpectErrorAt(WithObjectOnLine4(std::string(R"x(<object type="sphere" name="B" position="(0,0,0)" dimension="(1)")x"
                                                R"x( dynamic="true" mass=")x") +
                                    mass + "\"/>"),
                  4, {"'mass'", "positive", std::string("'") + mass + "'"});
  }
}

TEST(EnvironmentReaderTest, NonNumericPosition) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(0,high,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'position'", "3 numbers", "'(0,high,0)'"});
}

TEST(EnvironmentReaderTest, NonFinitePosition) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(0,inf,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'position'", "'(0,inf,0)'"});
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(0,nan,0)" dimension="(1,1,1)"/>)x"), 4,
                {"'position'", "'(0,nan,0)'"});
}

TEST(EnvironmentReaderTest, WrongTupleLength) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(1,2)" dimension="(1,1,1)"/>)x"), 4,
                {"'position'", "3 numbers", "'(1,2)'"});
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(1,2,3)" dimension="(1,1)"/>)x"), 4,
                {"'dimension'", "3 numbers"});
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="sphere" name="B" position="(1,2,3)" dimension="(1,1,1)"/>)x"), 4,
                {"'dimension'", "1 numbers"});
  ExpectErrorAt(
      WithObjectOnLine4(R"x(<object type="box" name="B" position="(1,2,3)" orientation="(1,2,3,4)" dimension="(1,1,1)"/>)x"),
      4, {"'orientation'", "3 numbers"});
}

TEST(EnvironmentReaderTest, NonPositiveDimension) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="B" position="(1,2,3)" dimension="(1,0,1)"/>)x"), 4,
                {"'dimension'", "positive"});
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="sphere" name="B" position="(1,2,3)" dimension="(-0.1)"/>)x"), 4,
                {"'dimension'", "positive"});
}

TEST(EnvironmentReaderTest, BadColour) {
  for (const char* color : {"reddish", "(300,0,0)", "(1,2)", "(0.5,0,0)"}) {
    SCOPED_TRACE(color);
    ExpectErrorAt(WithObjectOnLine4(std::string(R"x(<object type="box" name="B" position="(1,2,3)" dimension="(1,1,1)")x"
                                                R"x( color=")x") +
                                    color + "\"/>"),
                  4, {"'color'", std::string("'") + color + "'"});
  }
}

TEST(EnvironmentReaderTest, BadBoolean) {
  ExpectErrorAt(
      WithObjectOnLine4(R"x(<object type="box" name="B" position="(1,2,3)" dimension="(1,1,1)" dynamic="yes" mass="1"/>)x"),
      4, {"'dynamic'", "true or false", "'yes'"});
}

TEST(EnvironmentReaderTest, DuplicateObjectNames) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="Good" position="(1,2,3)" dimension="(1,1,1)"/>)x"), 4,
                {"'Good'", "twice"});
}

TEST(EnvironmentReaderTest, AgentNameDuplicatesObjectName) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Environment>",
                       R"x(<object type="box" name="Robot" position="(0,0,0)" dimension="(1,1,1)"/>)x", "</Environment>",
                       "<Agent>", R"x(<ASeries name="Robot"/>)x", "</Agent>", "</ORCS>"}),
                6, {"'Robot'", "twice"});
}

TEST(EnvironmentReaderTest, ReservedNameFloor) {
  ExpectErrorAt(WithObjectOnLine4(R"x(<object type="box" name="Floor" position="(1,2,3)" dimension="(1,1,1)"/>)x"), 4,
                {"'Floor'", "reserved"});
}

TEST(EnvironmentReaderTest, UnknownAgentType) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", R"x(<ASeries name="A"/>)x", R"x(<Nao name="B"/>)x",
                       "</Agent>", "</ORCS>"}),
                4, {"unknown agent type", "<Nao>"});
}

TEST(EnvironmentReaderTest, UnknownAgentAttribute) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", "", R"x(<ASeries name="A" scale="2"/>)x", "</Agent>",
                       "</ORCS>"}),
                4, {"unknown attribute", "scale"});
}

TEST(EnvironmentReaderTest, ReadsHoldBodyAndPendulumRig) {
  const EnvironmentDescription env = EnvironmentReader::ReadString(
      Lines({R"x(<ORCS version="1.0">)x", "<Agent>",
             R"x(<ASeries name="Held" position="(0,0.05,0)" holdBody="Middle/UpperBody"/>)x",
             R"x(<Pendulum name="Rig" position="(1,0.5,0)" poleMass="0.75" poleLength="0.4"/>)x", "<Pendulum/>",
             "</Agent>", "</ORCS>"}),
      kSource);
  ASSERT_EQ(env.agents.size(), 3u);
  EXPECT_EQ(env.agents[0].type, "ASeries");
  EXPECT_EQ(env.agents[0].hold_body, "Middle/UpperBody");
  EXPECT_EQ(env.agents[1].type, "Pendulum");
  EXPECT_EQ(env.agents[1].pole_mass, 0.75);
  EXPECT_EQ(env.agents[1].pole_length, 0.4);
  EXPECT_EQ(env.agents[2].name, "Pendulum");  // the rig's default name
  EXPECT_EQ(env.agents[2].pole_mass, 0.5);
  EXPECT_EQ(env.agents[2].pole_length, 0.3);
}

TEST(EnvironmentReaderTest, HoldBodyMustBeAnASeriesBody) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", R"x(<ASeries name="A" holdBody="Middle/Tail"/>)x",
                       "</Agent>", "</ORCS>"}),
                3, {"holdBody", "'Middle/Tail'"});
}

TEST(EnvironmentReaderTest, PendulumNeedsPositivePoleAndHasNoHoldBody) {
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", R"x(<Pendulum poleMass="0"/>)x", "</Agent>",
                       "</ORCS>"}),
                3, {"poleMass"});
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", R"x(<Pendulum poleLength="-1"/>)x", "</Agent>",
                       "</ORCS>"}),
                3, {"poleLength"});
  ExpectErrorAt(Lines({R"x(<ORCS version="1.0">)x", "<Agent>", R"x(<Pendulum holdBody="Pole"/>)x", "</Agent>",
                       "</ORCS>"}),
                3, {"unknown attribute", "holdBody"});
}

// ---------------------------------------------------------------------------------------------------------
// Files

class EnvironmentReaderFileTest : public ::testing::Test {
 protected:
  TempDir dir_;
};

TEST_F(EnvironmentReaderFileTest, NonexistentFileIsNamed) {
  const std::string file = dir_.PathOf("missing.xml");
  try {
    EnvironmentReader::ReadFile(file);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), StartsWith(file + ": "));
    EXPECT_THAT(error.what(), HasSubstr("cannot read"));
    EXPECT_EQ(error.source(), file);
  }
}

TEST_F(EnvironmentReaderFileTest, DirectoryIsNotAFile) {
  const std::string file = dir_.path().string();
  try {
    EnvironmentReader::ReadFile(file);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), StartsWith(file + ": "));
    EXPECT_THAT(error.what(), HasSubstr("not a regular file (a directory)"));
  }
}

TEST_F(EnvironmentReaderFileTest, ErrorsInAFileNameTheFileAndLine) {
  const std::string file = dir_.Write(
      "bad.xml",
      WithObjectOnLine4(R"x(<object type="box" name="B" position="(0,0,0)" dimension="(1,1,1)" mass="x"/>)x"));
  try {
    EnvironmentReader::ReadFile(file);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), StartsWith(file + ":4: "));
    EXPECT_THAT(error.what(), HasSubstr("'mass'"));
    EXPECT_EQ(error.line(), 4);
  }
}

TEST_F(EnvironmentReaderFileTest, ReadFileMatchesReadString) {
  const std::string xml = WithObjectOnLine4(R"x(<object type="sphere" name="S" position="(0,1,0)" dimension="(0.1)"/>)x");
  const std::string file = dir_.Write("good.xml", xml);
  const EnvironmentDescription from_file = EnvironmentReader::ReadFile(file);
  EXPECT_EQ(from_file.source, file);
  ASSERT_EQ(from_file.objects.size(), 2u);
  EXPECT_EQ(from_file.objects[1].name, "S");
  EXPECT_EQ(from_file.objects[1].position, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(from_file.objects[1].line, 4);
}

}  // namespace
}  // namespace orcs::scene
