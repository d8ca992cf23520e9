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
  ASSERT_EQ(EffectCatalogue().size(), 12u);
  for (const EffectDescription& effect : EffectCatalogue()) {
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

}  // namespace
}  // namespace orcs::identify
