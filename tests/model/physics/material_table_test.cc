#include "model/physics/material_table.h"

#include <gtest/gtest.h>

namespace orcs::physics {
namespace {

constexpr int kPlasticsWhite = 0;
constexpr int kPlasticsGray = 1;
constexpr int kAbs = 2;
constexpr int kLatex = 3;
constexpr int kPvc = 4;
constexpr int kWood = 5;
constexpr int kCarpet = 6;
constexpr int kDefault = 7;
constexpr int kLight = 8;

ContactMaterial Table(int first, int second) {
  return MaterialTable::Lookup(first, second, {}, {}, CustomMaterial{}, CustomMaterial{});
}

TEST(MaterialTableTest, IndicesFollowTheOriginalOrder) {
  const char* names[] = {"PlasticsWhite", "PlasticsGray", "ABS",   "Latex",   "PVC",    "Wood",
                         "Carpet",        "Default",      "Light", "Custom1", "Custom2"};
  ASSERT_EQ(MaterialTable::kCount, 11);
  for (int i = 0; i < MaterialTable::kCount; ++i) {
    EXPECT_EQ(MaterialTable::IndexOf(names[i]), i) << names[i];
    EXPECT_EQ(MaterialTable::NameOf(i), names[i]);
  }
}

TEST(MaterialTableTest, NamesAreCaseInsensitive) {
  EXPECT_EQ(MaterialTable::IndexOf("abs"), kAbs);
  EXPECT_EQ(MaterialTable::IndexOf("pLaStIcSwHiTe"), kPlasticsWhite);
  EXPECT_EQ(MaterialTable::IndexOf("CUSTOM2"), MaterialTable::kCustom2);
}

TEST(MaterialTableTest, UnknownNamesAndIndices) {
  EXPECT_EQ(MaterialTable::IndexOf("None"), MaterialTable::kUnknown);
  EXPECT_EQ(MaterialTable::IndexOf(""), MaterialTable::kUnknown);
  EXPECT_EQ(MaterialTable::IndexOf("AB"), MaterialTable::kUnknown);
  EXPECT_EQ(MaterialTable::IndexOf("ABS "), MaterialTable::kUnknown);
  EXPECT_EQ(MaterialTable::NameOf(MaterialTable::kUnknown), "");
  EXPECT_EQ(MaterialTable::NameOf(11), "");
}

TEST(MaterialTableTest, StaticFrictionCells) {
  EXPECT_DOUBLE_EQ(Table(kLatex, kPvc).static_friction, 0.83462);
  EXPECT_DOUBLE_EQ(Table(kPvc, kAbs).static_friction, 0.20874);
  EXPECT_DOUBLE_EQ(Table(kPlasticsGray, kAbs).static_friction, 0.6782);
  EXPECT_DOUBLE_EQ(Table(kCarpet, kLatex).static_friction, 1.25193);
  EXPECT_DOUBLE_EQ(Table(kPlasticsWhite, kPlasticsWhite).static_friction, 0.11935);
  EXPECT_DOUBLE_EQ(Table(kDefault, kPlasticsWhite).static_friction, 0.83462);
  EXPECT_DOUBLE_EQ(Table(kLatex, kLatex).static_friction, 0.0);
  EXPECT_DOUBLE_EQ(Table(kDefault, kLight).static_friction, 0.0);
}

TEST(MaterialTableTest, DynamicFrictionCells) {
  EXPECT_DOUBLE_EQ(Table(kPlasticsWhite, kPvc).dynamic_friction, 0.15516);
  EXPECT_DOUBLE_EQ(Table(kPvc, kPlasticsGray).dynamic_friction, 0.25034);
  EXPECT_DOUBLE_EQ(Table(kWood, kLatex).dynamic_friction, 1.1923);
  EXPECT_DOUBLE_EQ(Table(kAbs, kCarpet).dynamic_friction, 0.47116);
  EXPECT_DOUBLE_EQ(Table(kPvc, kPvc).dynamic_friction, 0.0);
}

TEST(MaterialTableTest, DefaultTimesPlasticsWhiteIsTheOneAsymmetricCell) {
  EXPECT_DOUBLE_EQ(Table(kPlasticsWhite, kDefault).dynamic_friction, 1.237);
  EXPECT_DOUBLE_EQ(Table(kDefault, kPlasticsWhite).dynamic_friction, 0.0);
  // Every other pair is symmetric in all three tables.
  for (int a = 0; a <= kLight; ++a) {
    for (int b = 0; b <= kLight; ++b) {
      if ((a == kDefault && b == kPlasticsWhite) || (a == kPlasticsWhite && b == kDefault)) continue;
      EXPECT_EQ(Table(a, b).static_friction, Table(b, a).static_friction) << a << "," << b;
      EXPECT_EQ(Table(a, b).dynamic_friction, Table(b, a).dynamic_friction) << a << "," << b;
      EXPECT_EQ(Table(a, b).restitution, Table(b, a).restitution) << a << "," << b;
    }
  }
}

// Issue 22, item 7. The original's manual says Default "behaves like Latex on Carpet"; its code (which orcs
// keeps) gives Default Latex-on-Carpet's dynamic coefficient but Latex-on-PVC's static one, against every
// material but Light. The check pins what orcs does, and the manual's half that holds.
TEST(MaterialTableTest, DefaultHasLatexOnCarpetsDynamicFrictionAndLatexOnPvcsStatic) {
  for (int other = 0; other < kLight; ++other) {
    EXPECT_DOUBLE_EQ(Table(kDefault, other).static_friction, Table(kLatex, kPvc).static_friction) << other;
    if (other == kPlasticsWhite) continue;  // the asymmetric cell, above
    EXPECT_DOUBLE_EQ(Table(kDefault, other).dynamic_friction, Table(kLatex, kCarpet).dynamic_friction) << other;
  }
  EXPECT_NE(Table(kDefault, kPvc).static_friction, Table(kLatex, kCarpet).static_friction)
      << "if Default's static friction became Latex-on-Carpet's, docs/model.md's item 7 must say so";
}

TEST(MaterialTableTest, RestitutionCells) {
  EXPECT_DOUBLE_EQ(Table(kPvc, kDefault).restitution, 0.5);
  EXPECT_DOUBLE_EQ(Table(kDefault, kWood).restitution, 0.5);
  EXPECT_DOUBLE_EQ(Table(kDefault, kCarpet).restitution, 0.1);
  EXPECT_DOUBLE_EQ(Table(kLatex, kPvc).restitution, 0.1);
  EXPECT_DOUBLE_EQ(Table(kLight, kLight).restitution, 0.1);
}

TEST(MaterialTableTest, Custom1TakesPrecedenceOverCustom2AndTheTable) {
  const CustomMaterial custom1{1.5, 0.7, 0.3};
  const CustomMaterial custom2{0.9, 0.4, 0.6};
  const ContactMaterial both = MaterialTable::Lookup(MaterialTable::kCustom2, MaterialTable::kCustom1, {}, {},
                                                     custom1, custom2);
  EXPECT_DOUBLE_EQ(both.static_friction, 1.5);
  EXPECT_DOUBLE_EQ(both.dynamic_friction, 0.7);
  EXPECT_DOUBLE_EQ(both.restitution, 0.3);

  const ContactMaterial with_table = MaterialTable::Lookup(kLatex, MaterialTable::kCustom2, {}, {}, custom1, custom2);
  EXPECT_DOUBLE_EQ(with_table.static_friction, 0.9);
  EXPECT_DOUBLE_EQ(with_table.dynamic_friction, 0.4);
  EXPECT_DOUBLE_EQ(with_table.restitution, 0.6);

  // A custom material wins over an unknown partner too.
  const ContactMaterial with_unknown =
      MaterialTable::Lookup(MaterialTable::kUnknown, MaterialTable::kCustom1, {}, {}, custom1, custom2);
  EXPECT_DOUBLE_EQ(with_unknown.static_friction, 1.5);
}

TEST(MaterialTableTest, CustomDefaultsAreTheRepositoryDefaults) {
  const ContactMaterial m = Table(MaterialTable::kCustom1, kAbs);
  EXPECT_DOUBLE_EQ(m.static_friction, 1.2);
  EXPECT_DOUBLE_EQ(m.dynamic_friction, 0.8);
  EXPECT_DOUBLE_EQ(m.restitution, 0.1);
}

TEST(MaterialTableTest, UnknownMaterialUsesTheBodiesFallback) {
  const BodyFrictionParameters first{0.3, 0.2, 0.5};
  const BodyFrictionParameters second{0.4, 0.1, 0.25};
  const ContactMaterial m =
      MaterialTable::Lookup(MaterialTable::kUnknown, kPvc, first, second, CustomMaterial{}, CustomMaterial{});
  EXPECT_DOUBLE_EQ(m.static_friction, 0.7);   // sum
  EXPECT_DOUBLE_EQ(m.dynamic_friction, 0.3);  // sum
  EXPECT_DOUBLE_EQ(m.restitution, 0.125);     // product, not the spec's sum (0.75)

  const ContactMaterial other_side =
      MaterialTable::Lookup(kAbs, MaterialTable::kUnknown, first, second, CustomMaterial{}, CustomMaterial{});
  EXPECT_DOUBLE_EQ(other_side.static_friction, 0.7);
  EXPECT_DOUBLE_EQ(other_side.restitution, 0.125);
}

}  // namespace
}  // namespace orcs::physics
