// What a diagnosis refits before it tries any candidate (BaseParameters): the motor model's own parameters — the
// physical servo's with R in place of kt and ke once the model sets a current limit — and the parameters of every
// catalogue effect the model already switches on, each starting at the model's value.
#include "model/identify/gap_diagnosis.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "model/identify/effect_catalogue.h"

namespace orcs::identify {
namespace {

std::vector<ValueAssignment> ServoModel(std::vector<ValueAssignment> more) {
  std::vector<ValueAssignment> model = {{"/Servo/Enabled", "T", "test.val", 1},
                                        {"/Servo/TorqueConstant", "0.3537", "test.val", 2},
                                        {"/Servo/Resistance", "3.401", "test.val", 3}};
  model.insert(model.end(), more.begin(), more.end());
  return model;
}

std::vector<std::string> Paths(const std::vector<FitParameter>& parameters) {
  std::vector<std::string> paths;
  for (const FitParameter& p : parameters) paths.push_back(p.path);
  return paths;
}

bool Has(const std::vector<std::string>& paths, const std::string& path) {
  return std::find(paths.begin(), paths.end(), path) != paths.end();
}

Rig PendulumRig(const std::vector<ValueAssignment>& model) {
  RigOptions options;
  options.kind = "pendulum";
  return MakeRig(options, "Pendulum", model);
}

TEST(GapBaseParametersTest, TheServoModelFitsKtAndKeWithoutACurrentLimitAndRInsteadWithOne) {
  const std::vector<ValueAssignment> free = ServoModel({});
  const std::vector<std::string> unlimited = Paths(BaseParameters(PendulumRig(free), free));
  EXPECT_TRUE(Has(unlimited, "/Servo/TorqueConstant"));
  EXPECT_TRUE(Has(unlimited, "/Servo/BackEmfConstant"));
  EXPECT_FALSE(Has(unlimited, "/Servo/Resistance"));

  const std::vector<ValueAssignment> limited_model = ServoModel({{"/Servo/CurrentLimit", "1.75", "test.val", 4}});
  const std::vector<FitParameter> limited = BaseParameters(PendulumRig(limited_model), limited_model);
  const std::vector<std::string> paths = Paths(limited);
  EXPECT_FALSE(Has(paths, "/Servo/TorqueConstant")) << "kt × the limit is the torque ceiling: kt stays the model's";
  EXPECT_FALSE(Has(paths, "/Servo/BackEmfConstant"));
  ASSERT_TRUE(Has(paths, "/Servo/Resistance"));
  for (const FitParameter& p : limited) {
    if (p.path == "/Servo/Resistance") {
      EXPECT_DOUBLE_EQ(p.start, 3.401);
    }
  }
  EXPECT_TRUE(Has(paths, "/Servo/CoulombFriction"));
}

TEST(GapBaseParametersTest, AnEffectTheModelSwitchesOnIsRefittedWithTheBaseFromTheModelsValue) {
  const std::vector<ValueAssignment> model =
      ServoModel({{"/Effects/GravityLoadFriction/Enabled", "T", "test.val", 4},
                  {"/Effects/GravityLoadFriction/Coefficient", "0.2", "test.val", 5}});
  const Rig rig = PendulumRig(model);
  const std::vector<const EffectDescription*> enabled = EnabledEffects(rig, model);
  ASSERT_EQ(enabled.size(), 1u);
  EXPECT_EQ(enabled[0]->name, "GravityLoadFriction");
  const std::vector<FitParameter> base = BaseParameters(rig, model);
  ASSERT_FALSE(base.empty());
  EXPECT_EQ(base.back().path, "/Effects/GravityLoadFriction/Coefficient");
  EXPECT_DOUBLE_EQ(base.back().start, 0.2);
  EXPECT_DOUBLE_EQ(base.back().lower, FindEffect("GravityLoadFriction")->parameters[0].lower);

  const std::vector<ValueAssignment> plain = ServoModel({});
  EXPECT_TRUE(EnabledEffects(PendulumRig(plain), plain).empty());
  EXPECT_EQ(BaseParameters(PendulumRig(plain), plain).size(), base.size() - 1);
}

}  // namespace
}  // namespace orcs::identify
