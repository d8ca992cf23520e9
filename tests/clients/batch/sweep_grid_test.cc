// The grid of orcs-batch sweep: parsing --param and enumerating the points.
#include "clients/batch/sweep_grid.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/input_error_of.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

TEST(SweepGridTest, ParsesAnAxis) {
  const SweepAxis axis = ParseSweepAxis("/AngularMotor/PID/Proportional=10:30:5");
  EXPECT_EQ(axis.path, "/AngularMotor/PID/Proportional");
  EXPECT_EQ(axis.low, 10);
  EXPECT_EQ(axis.high, 30);
  EXPECT_EQ(axis.steps, 5);
  EXPECT_EQ(axis.ValueAt(0), 10);
  EXPECT_EQ(axis.ValueAt(1), 15);
  EXPECT_EQ(axis.ValueAt(4), 30);
}

TEST(SweepGridTest, TheLastValueIsExactlyHigh) {
  const SweepAxis axis = ParseSweepAxis("/X=0.1:0.7:7");
  EXPECT_EQ(axis.ValueAt(6), 0.7);
  EXPECT_EQ(axis.ValueAt(0), 0.1);
}

TEST(SweepGridTest, RejectsBadAxesNamingTheOption) {
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X"); }), HasSubstr("--param '/X': expected PATH=LOW:HIGH:STEPS"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("X=1:2:3"); }), HasSubstr("starting with '/'"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=1:2"); }), HasSubstr("found 2 fields"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=a:2:3"); }), HasSubstr("LOW expected a finite number"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=1:nan:3"); }), HasSubstr("HIGH expected a finite number"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=3:2:3"); }), HasSubstr("LOW 3 is above HIGH 2"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=1:2:0"); }), HasSubstr("STEPS expected an integer"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=1:2:2.5"); }), HasSubstr("STEPS expected an integer"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/X=1:2:1"); }), HasSubstr("STEPS 1 needs LOW equal to HIGH"));
}

TEST(SweepGridTest, EnumeratesEveryCombinationFirstAxisSlowest) {
  const std::vector<SweepPoint> points = SweepGrid({ParseSweepAxis("/A=0:1:2"), ParseSweepAxis("/B=10:30:3")});
  ASSERT_EQ(points.size(), 6u);
  const std::vector<std::pair<double, double>> expected = {{0, 10}, {0, 20}, {0, 30}, {1, 10}, {1, 20}, {1, 30}};
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(points[i].size(), 2u);
    EXPECT_EQ(points[i][0].first, "/A");
    EXPECT_EQ(points[i][0].second, expected[i].first) << i;
    EXPECT_EQ(points[i][1].first, "/B");
    EXPECT_EQ(points[i][1].second, expected[i].second) << i;
  }
}

TEST(SweepGridTest, RejectsAPathSweptTwiceAndGridsTooLarge) {
  EXPECT_THAT(InputErrorOf([] { SweepGrid({ParseSweepAxis("/A=0:1:2"), ParseSweepAxis("/A=0:1:3")}); }),
              HasSubstr("/A is swept twice"));
  EXPECT_THAT(InputErrorOf([] { SweepGrid({ParseSweepAxis("/A=0:1:100"), ParseSweepAxis("/B=0:1:100")}, 5000); }),
              HasSubstr("more than 5000 points"));
}

TEST(SweepGridTest, ParsesAListOfCategories) {
  const SweepAxis axis = ParseSweepAxis("/Sim/Floor/Material=PVC,Wood,Carpet");
  EXPECT_TRUE(axis.categorical());
  EXPECT_EQ(axis.categories, (std::vector<std::string>{"PVC", "Wood", "Carpet"}));
  EXPECT_EQ(axis.steps, 3);
  EXPECT_EQ(axis.GridValue(1), SweepValue("Wood", 1));
  EXPECT_EQ(axis.GridValue(1).OverrideText(), "Wood");
  EXPECT_EQ(ParseSweepAxis("/Flag=true,false").categories.size(), 2u);  // any values the repository reads
  EXPECT_FALSE(ParseSweepAxis("/X=1:2:3").categorical());
  EXPECT_EQ(ParseSweepAxis("/X=1:2:3").GridValue(2).OverrideText(), "2");
}

TEST(SweepGridTest, AGridOverNumbersAndCategoriesCarriesTheCategoryNames) {
  const std::vector<SweepPoint> points =
      SweepGrid({ParseSweepAxis("/A=0:1:2"), ParseSweepAxis("/Sim/Floor/Material=Wood,Carpet")});
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points[1][1].second.text, "Carpet");
  EXPECT_EQ(points[1][1].second.number, 1);
  EXPECT_EQ(points[2][0].second.number, 1);
  EXPECT_EQ(points[2][1].second.text, "Wood");
}

TEST(SweepGridTest, RejectsBadCategoriesNamingTheOption) {
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/Sim/Floor/Material=PVC,Wod"); }),
              HasSubstr("--param '/Sim/Floor/Material=PVC,Wod': 'Wod' is not a material; expected one of PlasticsWhite, "
                        "PlasticsGray, ABS, Latex, PVC, Wood, Carpet, Default, Light, Custom1, Custom2"));
  EXPECT_NO_THROW(ParseSweepAxis("/Sim/Box/Material=wood")) << "material names are case-insensitive, as in the table";
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/M=a,,b"); }), HasSubstr("--param '/M=a,,b': expected a list"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/M="); }), HasSubstr("without empty ones"));
  EXPECT_THAT(InputErrorOf([] { ParseSweepAxis("/M=a,b,a"); }), HasSubstr("the value 'a' is listed twice"));
}

TEST(SweepGridTest, LatinHypercubeAxesAreIntervalsOrCategories) {
  const SweepAxis axis = ParseSweepAxis("/AngularMotor/PID/Proportional=10:30", SweepSampling::kLatinHypercube);
  EXPECT_EQ(axis.low, 10);
  EXPECT_EQ(axis.high, 30);
  EXPECT_EQ(axis.steps, 0);
  EXPECT_TRUE(ParseSweepAxis("/Sim/Floor/Material=PVC,Wood", SweepSampling::kLatinHypercube).categorical());
  const auto lhs_error = [](const std::string& text) {
    return InputErrorOf([&] { ParseSweepAxis(text, SweepSampling::kLatinHypercube); });
  };
  EXPECT_THAT(lhs_error("/X=1:2:3"), HasSubstr("--param '/X=1:2:3': expected LOW:HIGH after '=' for --sample lhs"));
  EXPECT_THAT(lhs_error("/X=2:1"), HasSubstr("--param '/X=2:1': LOW 2 is above HIGH 1"));
  EXPECT_THAT(lhs_error("/X=1:inf"), HasSubstr("HIGH expected a finite number"));
  EXPECT_THAT(lhs_error("/X"), HasSubstr("--param '/X': expected PATH=LOW:HIGH or PATH=V1,V2,..."));
}

}  // namespace
}  // namespace orcs::batch
