#include "model/control/keyframe_player.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/input_error_of.h"

namespace orcs::control {
namespace {

using test_support::InputErrorOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// The values an agent with motors "A" (range −90…90) and "B/C" (range 0…150) registers.
class KeyframePlayerTest : public ::testing::Test {
 protected:
  KeyframePlayerTest() {
    AddMotor("A", -90, 90);
    AddMotor("B/C", 0, 150);
  }
  void AddMotor(const std::string& name, double min, double max) {
    const std::string prefix = "/Sim/Robot/" + name + "/";
    values_.Add(prefix + "DesiredAngle", 0.0);
    values_.Add(prefix + "DesiredTorque", 0.5);
    values_.Add(prefix + "MinAngle", min);
    values_.Add(prefix + "MaxAngle", max);
  }
  std::vector<double> Inputs() const {
    return {values_.Get("/Sim/Robot/A/DesiredAngle").as_double(), values_.Get("/Sim/Robot/A/DesiredTorque").as_double(),
            values_.Get("/Sim/Robot/B/C/DesiredAngle").as_double(),
            values_.Get("/Sim/Robot/B/C/DesiredTorque").as_double()};
  }
  KeyframePlayer Player(const std::string& text) {
    return KeyframePlayer(ParseKeyframeRecord(text, "m.csv", 2), "Robot", motors_, values_);
  }

  VariableRepository values_;
  std::vector<std::string> motors_{"A", "B/C"};
};

TEST_F(KeyframePlayerTest, RowTakesEffectAtFirstStepWhoseTimeReachesIt) {
  KeyframePlayer player = Player("# layout: raw\n30,10,1,20,1\n50,-10,0,40,0.25\n");
  player.Apply(0.0);
  player.Apply(0.02);
  EXPECT_THAT(Inputs(), ElementsAre(0.0, 0.5, 0.0, 0.5));  // before the first row: untouched
  player.Apply(0.01 + 0.01 + 0.01);                        // 29.999999999999996 ms: the 30 ms row
  EXPECT_THAT(Inputs(), ElementsAre(10.0, 1.0, 20.0, 1.0));
  player.Apply(0.04);
  EXPECT_THAT(Inputs(), ElementsAre(10.0, 1.0, 20.0, 1.0));
  player.Apply(0.05);
  EXPECT_THAT(Inputs(), ElementsAre(-10.0, 0.0, 40.0, 0.25));
}

TEST_F(KeyframePlayerTest, SkippedRowsGiveTheLatestReachedRow) {
  KeyframePlayer player = Player("# layout: raw\n0,1,1,1,1\n10,2,1,2,1\n20,3,1,3,1\n");
  player.Apply(0.5);  // a long step: rows at 0, 10 and 20 ms all reached, the last one counts
  EXPECT_THAT(Inputs(), ElementsAre(3.0, 1.0, 3.0, 1.0));
}

TEST_F(KeyframePlayerTest, DoesNotOverwriteOtherWritersBetweenRows) {
  KeyframePlayer player = Player("# layout: raw\n0,5,1,5,1\n100,6,1,6,1\n");
  player.Apply(0.0);
  values_.Get("/Sim/Robot/A/DesiredAngle").Set(42.0);  // e.g. an OSP client or a value file
  player.Apply(0.05);
  EXPECT_EQ(values_.Get("/Sim/Robot/A/DesiredAngle").as_double(), 42.0);
}

TEST_F(KeyframePlayerTest, ResetReplaysFromTheStart) {
  KeyframePlayer player = Player("# layout: raw\n0,5,1,5,1\n100,6,1,6,1\n");
  player.Apply(0.2);
  EXPECT_EQ(Inputs()[0], 6.0);
  player.Reset();
  player.Apply(0.0);
  EXPECT_EQ(Inputs()[0], 5.0);
}

TEST_F(KeyframePlayerTest, OutOfRangeInputsAreClampedWithOneWarningPerInput) {
  KeyframePlayer player = Player("# layout: raw\n0,100,1,-5,2\n10,120,1,0,1\n20,0,-3,0,1\n");
  ASSERT_EQ(player.warnings().size(), 4u);
  EXPECT_EQ(player.warnings()[0],
            "m.csv:2: warning: A/DesiredAngle 100 is outside -90…90; clamped here and wherever else it is outside");
  EXPECT_THAT(player.warnings()[1], HasSubstr("m.csv:4: warning: A/DesiredTorque -3 is outside -1…1"));
  EXPECT_THAT(player.warnings()[2], HasSubstr("m.csv:2: warning: B/C/DesiredAngle -5 is outside 0…150"));
  EXPECT_THAT(player.warnings()[3], HasSubstr("m.csv:2: warning: B/C/DesiredTorque 2 is outside -1…1"));
  player.Apply(0.0);
  EXPECT_THAT(Inputs(), ElementsAre(90.0, 1.0, 0.0, 1.0));
  player.Apply(0.01);
  EXPECT_EQ(Inputs()[0], 90.0);
  player.Apply(0.02);
  EXPECT_EQ(Inputs()[1], -1.0);
}

TEST_F(KeyframePlayerTest, RecordForAnotherMotorCountIsRefused) {
  EXPECT_EQ(InputErrorOf([&] {
              KeyframePlayer(ParseKeyframeRecord("0,1,1\n", "m.csv", 1), "Robot", motors_, values_);
            }),
            "m.csv: the record has inputs for 1 motor, agent 'Robot' has 2");
}

}  // namespace
}  // namespace orcs::control
