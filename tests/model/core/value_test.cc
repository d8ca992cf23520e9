#include "model/core/value.h"

#include <gtest/gtest.h>

#include <map>

#include <cstdint>
#include <string>
#include <vector>

namespace orcs {
namespace {

TEST(ValueTest, TypesAndTypeNames) {
  EXPECT_EQ(Value(true).type(), ValueType::kBool);
  EXPECT_EQ(Value(1).type(), ValueType::kInt);
  EXPECT_EQ(Value(std::int64_t{1}).type(), ValueType::kInt);
  EXPECT_EQ(Value(1.0).type(), ValueType::kDouble);
  EXPECT_EQ(Value("s").type(), ValueType::kString);
  EXPECT_EQ(Value(std::string("s")).type(), ValueType::kString);
  EXPECT_EQ(Value(Color{}).type(), ValueType::kColor);
  EXPECT_EQ(Value(Eigen::Vector3d(1, 2, 3)).type(), ValueType::kVector3);
  EXPECT_EQ(Value(Eigen::Quaterniond::Identity()).type(), ValueType::kQuaternion);
  EXPECT_EQ(ValueTypeName(ValueType::kBool), "bool");
  EXPECT_EQ(ValueTypeName(ValueType::kInt), "int");
  EXPECT_EQ(ValueTypeName(ValueType::kDouble), "double");
  EXPECT_EQ(ValueTypeName(ValueType::kString), "string");
  EXPECT_EQ(ValueTypeName(ValueType::kColor), "color");
  EXPECT_EQ(ValueTypeName(ValueType::kVector3), "vector3d");
  EXPECT_EQ(ValueTypeName(ValueType::kQuaternion), "quaternion");
}

TEST(ValueTest, BoolPrintsTAndF) {
  Value value(true);
  EXPECT_EQ(value.ToString(), "T");
  value.Set(false);
  EXPECT_EQ(value.ToString(), "F");
}

TEST(ValueTest, BoolParsesTFTrueFalseOneZero) {
  Value value(false);
  for (const char* yes : {"T", "true", "1", "TRUE", " t "}) {
    value.Set(false);
    EXPECT_EQ(value.SetFromString(yes), "") << yes;
    EXPECT_TRUE(value.as_bool()) << yes;
  }
  for (const char* no : {"F", "false", "0", "False", " f "}) {
    value.Set(true);
    EXPECT_EQ(value.SetFromString(no), "") << no;
    EXPECT_FALSE(value.as_bool()) << no;
  }
}

TEST(ValueTest, BoolRejectsOtherText) {
  Value value(true);
  for (const char* bad : {"", "yes", "2", "TF", "truee"}) {
    EXPECT_EQ(value.SetFromString(bad), "T or F") << bad;
    EXPECT_TRUE(value.as_bool());
  }
}

TEST(ValueTest, IntPrintsAndParses) {
  Value value(5);
  EXPECT_EQ(value.ToString(), "5");
  EXPECT_EQ(value.SetFromString(" -12 "), "");
  EXPECT_EQ(value.as_int(), -12);
  EXPECT_EQ(value.ToString(), "-12");
  EXPECT_EQ(value.SetFromString("9007199254740993"), "");  // not representable as a double
  EXPECT_EQ(value.as_int(), std::int64_t{9007199254740993});
  EXPECT_EQ(value.ToString(), "9007199254740993");
}

TEST(ValueTest, IntRejectsNonIntegersAndKeepsItsValue) {
  Value value(5);
  for (const char* bad : {"1.5", "abc", "", "3x"}) {
    EXPECT_EQ(value.SetFromString(bad), "an integer") << bad;
    EXPECT_EQ(value.as_int(), 5);
  }
}

TEST(ValueTest, DoublePrintsShortestAndParses) {
  Value value(0.1);
  EXPECT_EQ(value.ToString(), "0.1");
  EXPECT_EQ(value.SetFromString("1e-3"), "");
  EXPECT_EQ(value.as_double(), 1e-3);
  EXPECT_EQ(value.ToString(), "0.001");
  const double third = 1.0 / 3.0;
  value.Set(third);
  Value copy(0.0);
  EXPECT_EQ(copy.SetFromString(value.ToString()), "");
  EXPECT_EQ(copy.as_double(), third);
}

TEST(ValueTest, DoubleRejectsNonNumbersAndKeepsItsValue) {
  Value value(2.5);
  for (const char* bad : {"abc", "", "nan", "1.5x", "(1,2,3)"}) {
    EXPECT_EQ(value.SetFromString(bad), "a number") << bad;
    EXPECT_EQ(value.as_double(), 2.5);
  }
}

TEST(ValueTest, StringKeepsTextAsItIs) {
  Value value("abc");
  EXPECT_EQ(value.ToString(), "abc");
  EXPECT_EQ(value.SetFromString(" with spaces, commas = and (1,2) "), "");
  EXPECT_EQ(value.as_string(), " with spaces, commas = and (1,2) ");
  EXPECT_EQ(value.ToString(), " with spaces, commas = and (1,2) ");
  EXPECT_EQ(value.SetFromString(""), "");
  EXPECT_EQ(value.as_string(), "");
}

TEST(ValueTest, ColorByName) {
  Value value(Color{1, 2, 3, 4});
  EXPECT_EQ(value.SetFromString("red"), "");
  EXPECT_EQ(value.as_color(), (Color{255, 0, 0, 255}));
  EXPECT_EQ(value.SetFromString(" LightGray "), "");
  EXPECT_EQ(value.as_color(), (Color{192, 192, 192, 255}));  // Qt's, as the original had
  EXPECT_EQ(value.SetFromString("transparent"), "");
  EXPECT_EQ(value.as_color(), (Color{0, 0, 0, 0}));
  EXPECT_EQ(ParseColor("blue"), (Color{0, 0, 255, 255}));
  EXPECT_FALSE(ParseColor("reddish").has_value());
}

// The original's names are Qt's global colours: every one of them, with Qt's values (issue 22, item 3).
TEST(ValueTest, EveryColourNameOfTheOriginalIsKnown) {
  const std::map<std::string, Color> qt = {
      {"white", {255, 255, 255, 255}}, {"black", {0, 0, 0, 255}},        {"red", {255, 0, 0, 255}},
      {"darkRed", {128, 0, 0, 255}},   {"green", {0, 255, 0, 255}},      {"darkGreen", {0, 128, 0, 255}},
      {"blue", {0, 0, 255, 255}},      {"darkBlue", {0, 0, 128, 255}},   {"cyan", {0, 255, 255, 255}},
      {"darkCyan", {0, 128, 128, 255}}, {"magenta", {255, 0, 255, 255}}, {"darkMagenta", {128, 0, 128, 255}},
      {"yellow", {255, 255, 0, 255}},  {"darkYellow", {128, 128, 0, 255}}, {"gray", {160, 160, 164, 255}},
      {"darkGray", {128, 128, 128, 255}}, {"lightGray", {192, 192, 192, 255}}, {"transparent", {0, 0, 0, 0}}};
  for (const auto& [name, color] : qt) EXPECT_EQ(ParseColor(name), color) << name;
  EXPECT_EQ(ParseColor("DARKYELLOW"), (Color{128, 128, 0, 255}));
}

TEST(ValueTest, ColorByTuple) {
  Value value(Color{});
  EXPECT_EQ(value.SetFromString("(10,20,30)"), "");
  EXPECT_EQ(value.as_color(), (Color{10, 20, 30, 255}));  // alpha defaults to opaque
  EXPECT_EQ(value.SetFromString("(10, 20, 30, 40)"), "");
  EXPECT_EQ(value.as_color(), (Color{10, 20, 30, 40}));
  EXPECT_EQ(value.ToString(), "(10,20,30,40)");
  Value copy(Color{});
  EXPECT_EQ(copy.SetFromString(value.ToString()), "");
  EXPECT_EQ(copy.as_color(), value.as_color());
}

TEST(ValueTest, ColorRejectsBadChannelsAndKeepsItsValue) {
  const Color original{1, 2, 3, 4};
  Value value(original);
  for (const char* bad : {"(256,0,0)", "(-1,0,0)", "(1.5,0,0)", "(1,2)", "(1,2,3,4,5)", "notacolour", "(a,b,c)"}) {
    const std::string expected = value.SetFromString(bad);
    EXPECT_NE(expected, "") << bad;
    EXPECT_NE(expected.find("colour"), std::string::npos) << expected;
    EXPECT_EQ(value.as_color(), original) << bad;
  }
}

TEST(ValueTest, Vector3PrintsAndParses) {
  Value value(Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(value.ToString(), "(1,2,3)");
  EXPECT_EQ(value.SetFromString("(0.1, -2, 1e-3)"), "");
  EXPECT_EQ(value.as_vector3(), Eigen::Vector3d(0.1, -2, 1e-3));
  EXPECT_EQ(value.ToString(), "(0.1,-2,0.001)");
  EXPECT_EQ(value.SetFromString("4 5 6"), "");
  EXPECT_EQ(value.as_vector3(), Eigen::Vector3d(4, 5, 6));
}

TEST(ValueTest, Vector3RejectsWrongArityAndKeepsItsValue) {
  Value value(Eigen::Vector3d(1, 2, 3));
  for (const char* bad : {"(1,2)", "(1,2,3,4)", "(1,,3)", "(1,a,3)", "", "1"}) {
    EXPECT_EQ(value.SetFromString(bad), "a vector (x,y,z)") << bad;
    EXPECT_EQ(value.as_vector3(), Eigen::Vector3d(1, 2, 3)) << bad;
  }
}

TEST(ValueTest, QuaternionPrintsAndParsesInWxyzOrder) {
  Value value(Eigen::Quaterniond(1, 0, 0, 0));
  EXPECT_EQ(value.ToString(), "(1,0,0,0)");
  EXPECT_EQ(value.SetFromString("(0.5,0.25,-0.125,2)"), "");
  const Eigen::Quaterniond q = value.as_quaternion();
  EXPECT_EQ(q.w(), 0.5);
  EXPECT_EQ(q.x(), 0.25);
  EXPECT_EQ(q.y(), -0.125);
  EXPECT_EQ(q.z(), 2.0);
  EXPECT_EQ(value.ToString(), "(0.5,0.25,-0.125,2)");
  value.Set(Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0));
  EXPECT_EQ(value.ToString(), "(0,1,0,0)");
}

TEST(ValueTest, QuaternionRejectsWrongArityAndKeepsItsValue) {
  Value value(Eigen::Quaterniond(1, 0, 0, 0));
  for (const char* bad : {"(1,0,0)", "(1,0,0,0,0)", "x"}) {
    EXPECT_EQ(value.SetFromString(bad), "a quaternion (w,x,y,z)") << bad;
    EXPECT_EQ(value.ToString(), "(1,0,0,0)") << bad;
  }
}

TEST(ValueTest, CheckStringReportsWithoutChanging) {
  Value value(2.5);
  int calls = 0;
  value.AddObserver([&calls](const Value&) { ++calls; });
  EXPECT_EQ(value.CheckString("7"), "");
  EXPECT_EQ(value.as_double(), 2.5);
  EXPECT_EQ(value.CheckString("x"), "a number");
  EXPECT_EQ(value.as_double(), 2.5);
  Value vector(Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(vector.CheckString("(4,5,6)"), "");
  EXPECT_EQ(vector.as_vector3(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(calls, 0);
}

TEST(ValueTest, ObserversFireOnChangeOnly) {
  Value value(1.0);
  std::vector<double> seen;
  value.AddObserver([&seen](const Value& changed) { seen.push_back(changed.as_double()); });
  value.Set(2.0);
  value.Set(2.0);                 // same value: silent
  value.SetFromString("2");       // same value by text: silent
  value.SetFromString("abc");     // parse error: silent
  value.SetFromString("3");
  value.Set(3.0);
  EXPECT_EQ(seen, (std::vector<double>{2.0, 3.0}));
}

TEST(ValueTest, ObserversFireForEveryTypeOnChange) {
  int calls = 0;
  const auto count = [&calls](const Value&) { ++calls; };
  Value b(false);
  Value i(1);
  Value s("a");
  Value c(Color{});
  Value v(Eigen::Vector3d::Zero());
  Value q(Eigen::Quaterniond::Identity());
  for (Value* value : {&b, &i, &s, &c, &v, &q}) value->AddObserver(count);
  b.Set(false);
  i.Set(1);
  s.Set("a");
  c.Set(Color{});
  v.Set(Eigen::Vector3d(0, 0, 0));
  q.Set(Eigen::Quaterniond::Identity());
  EXPECT_EQ(calls, 0);
  b.Set(true);
  i.Set(2);
  s.Set("b");
  c.Set(Color{0, 0, 0, 1});
  v.Set(Eigen::Vector3d(0, 0, 1));
  q.Set(Eigen::Quaterniond(0, 1, 0, 0));
  EXPECT_EQ(calls, 6);
  EXPECT_EQ(s.SetFromString("b"), "");
  EXPECT_EQ(v.SetFromString("(0,0,1)"), "");
  EXPECT_EQ(calls, 6);
}

TEST(ValueTest, ObserverSeesTheNewValue) {
  Value value(Eigen::Vector3d(1, 2, 3));
  Eigen::Vector3d seen = Eigen::Vector3d::Zero();
  value.AddObserver([&seen](const Value& changed) { seen = changed.as_vector3(); });
  value.SetFromString("(4,5,6)");
  EXPECT_EQ(seen, Eigen::Vector3d(4, 5, 6));
}

TEST(ValueTest, RemoveObserverStopsOnlyThatObserver) {
  Value value(0);
  int first = 0;
  int second = 0;
  const int first_id = value.AddObserver([&first](const Value&) { ++first; });
  const int second_id = value.AddObserver([&second](const Value&) { ++second; });
  EXPECT_NE(first_id, second_id);
  value.Set(1);
  value.RemoveObserver(first_id);
  value.Set(2);
  EXPECT_EQ(first, 1);
  EXPECT_EQ(second, 2);
  value.RemoveObserver(second_id);
  value.Set(3);
  EXPECT_EQ(second, 2);
  value.RemoveObserver(12345);  // unknown id: no effect
  EXPECT_EQ(value.as_int(), 3);
}

TEST(ValueTest, ChoicesRefuseOtherTextAndKeepTheirOwnSpelling) {
  Value engine(std::string("ODE"));
  engine.SetChoices({"ODE", "MuJoCo"});
  EXPECT_EQ(engine.CheckString("Bullet"), "one of ODE, MuJoCo");
  EXPECT_EQ(engine.SetFromString("Bullet"), "one of ODE, MuJoCo");
  EXPECT_EQ(engine.as_string(), "ODE");  // unchanged
  int heard = 0;
  engine.AddObserver([&heard](const Value&) { ++heard; });
  EXPECT_EQ(engine.SetFromString("mujoco"), "");
  EXPECT_EQ(engine.as_string(), "MuJoCo");
  EXPECT_EQ(engine.SetFromString("MUJOCO"), "");  // the same choice: no change, no notice
  EXPECT_EQ(heard, 1);
}

}  // namespace
}  // namespace orcs
