// The effect catalogue against the motor model's value table: every path a fit adjusts or switches exists.
#include "model/identify/effect_catalogue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>

#include "model/aseries/motor_effects.h"

namespace orcs::identify {
namespace {

using aseries::kMotorEffectsTable;

TEST(EffectCatalogueTest, CatalogueFitsOnlyParametersThatTheRepositoryHas) {
  // orcs-gap switches an effect with /Effects/<name>/Enabled and fits the listed paths: each must be a field
  // of the table, the range ordered (and positive where the search is log-scaled), and the entry found by its name.
  const auto in_table = [](std::string_view path) {
    return std::any_of(kMotorEffectsTable.begin(), kMotorEffectsTable.end(),
                       [&](const auto& field) { return field.path == path; });
  };
  ASSERT_EQ(EffectCatalogue().size(), 13u);
  for (const EffectDescription& effect : EffectCatalogue()) {
    if (!effect.switched) {
      // A property of a link (LinkMass): its parameter is built per link from the robot's values, no switch.
      EXPECT_TRUE(effect.per_link) << effect.name;
      EXPECT_TRUE(effect.parameters.empty()) << effect.name;
      continue;
    }
    EXPECT_TRUE(in_table("/Effects/" + std::string(effect.name) + "/Enabled")) << effect.name;
    EXPECT_EQ(FindEffect(effect.name), &effect);
    EXPECT_FALSE(effect.quantity.empty()) << effect.name;
    ASSERT_FALSE(effect.parameters.empty()) << effect.name;
    for (const FitParameter& parameter : effect.parameters) {
      EXPECT_TRUE(in_table(parameter.path)) << parameter.path;
      EXPECT_TRUE(parameter.path.starts_with("/Effects/" + std::string(effect.name) + "/")) << parameter.path;
      if (parameter.log_scale) {
        EXPECT_GT(parameter.lower, 0.0) << parameter.path;  // a log-scale search needs a positive range
      } else {
        EXPECT_GE(parameter.lower, 0.0) << parameter.path;
      }
      EXPECT_LT(parameter.lower, parameter.upper) << parameter.path;
    }
  }
  EXPECT_EQ(FindEffect("Cogging"), nullptr);
}

// The relations a tied verdict states (docs/gap.md, "When two effects explain the data") name catalogue effects, in
// either order; only an exact nesting (GearEfficiency at Curvature 0 is LoadFriction) lets the simpler be named alone.
TEST(EffectCatalogueTest, RelationsNameCatalogueEffectsInEitherOrder) {
  const EffectRelation* lugre = FindRelation("Stribeck", "LuGre");
  ASSERT_NE(lugre, nullptr);
  EXPECT_EQ(lugre, FindRelation("LuGre", "Stribeck"));
  EXPECT_FALSE(lugre->nested);
  const EffectRelation* gear = FindRelation("LoadFriction", "GearEfficiency");
  ASSERT_NE(gear, nullptr);
  EXPECT_TRUE(gear->nested);
  EXPECT_EQ(gear->first, "GearEfficiency");  // the one that contains the other
  EXPECT_EQ(FindRelation("Backlash", "LuGre"), nullptr);
  for (const std::string_view name : {"LuGre", "Stribeck", "BackDrive", "LoadFriction", "GravityLoadFriction",
                                      "Backlash", "DeadBand", "TransportDelay", "RotorInertia", "Elasticity"}) {
    EXPECT_NE(FindEffect(name), nullptr) << name;
  }
  const EffectDescription* mass = FindEffect("LinkMass");
  ASSERT_NE(mass, nullptr);
  EXPECT_TRUE(mass->needs_accelerometers);
}

}  // namespace
}  // namespace orcs::identify
