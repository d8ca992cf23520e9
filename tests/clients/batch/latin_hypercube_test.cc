// The Latin hypercube of orcs-batch sweep --sample lhs: one sample per stratum on every axis, within bounds,
// categories in equal shares, the same points for the same seed.
#include "clients/batch/latin_hypercube.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "tests/support/input_error_of.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

using test_support::InputErrorOf;
using ::testing::HasSubstr;

SweepAxis Lhs(const std::string& text) { return ParseSweepAxis(text, SweepSampling::kLatinHypercube); }

std::vector<double> Values(const std::vector<SweepPoint>& points, std::size_t axis) {
  std::vector<double> values;
  for (const SweepPoint& point : points) values.push_back(point.at(axis).second.number);
  return values;
}

// True when the k-th smallest value lies in stratum k, [low + k·w, low + (k+1)·w] — which, for N values and N
// strata, is exactly "one sample per stratum".
bool OnePerStratum(std::vector<double> values, double low, double high) {
  std::sort(values.begin(), values.end());
  const double width = (high - low) / static_cast<double>(values.size());
  const double slack = 1e-12 * (high - low);
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double bottom = low + static_cast<double>(k) * width;
    if (values[k] < bottom - slack || values[k] > bottom + width + slack) return false;
  }
  return true;
}

TEST(LatinHypercubeTest, EveryAxisHasExactlyOneSamplePerStratumWithinItsBounds) {
  const std::vector<SweepAxis> axes = {Lhs("/A=0:10"), Lhs("/B=-1:1"), Lhs("/C=1e-3:1.5e-3")};
  const std::vector<SweepPoint> points = LatinHypercube(axes, 57, 7);
  ASSERT_EQ(points.size(), 57u);
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const std::vector<double> values = Values(points, a);
    EXPECT_TRUE(OnePerStratum(values, axes[a].low, axes[a].high)) << axes[a].path;
    for (double v : values) {
      EXPECT_GE(v, axes[a].low);
      EXPECT_LE(v, axes[a].high);
    }
    EXPECT_EQ(points[0][a].first, axes[a].path);
    EXPECT_FALSE(points[0][a].second.categorical());
  }
}

TEST(LatinHypercubeTest, SamplesLieAnywhereInTheirStratumNotAtItsCentre) {
  const std::vector<SweepPoint> points = LatinHypercube({Lhs("/A=0:1")}, 200, 3);
  double lowest = 1.0, highest = 0.0;
  for (double v : Values(points, 0)) {
    const double place = v * 200 - std::floor(v * 200);  // where inside its stratum, 0..1
    lowest = std::min(lowest, place);
    highest = std::max(highest, place);
  }
  EXPECT_LT(lowest, 0.1);
  EXPECT_GT(highest, 0.9);
}

TEST(LatinHypercubeTest, TheAxesArePairedByAPermutationNotInStep) {
  const std::vector<SweepPoint> points = LatinHypercube({Lhs("/A=0:1"), Lhs("/B=0:1")}, 100, 11);
  // Rank correlation of the two axes: 1 if the strata were paired in order; a random pairing gives ~0 ± 0.1.
  const std::vector<double> a = Values(points, 0), b = Values(points, 1);
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - 0.5) * (b[i] - 0.5);
  const double correlation = sum / static_cast<double>(a.size()) * 12.0;  // uniform variance is 1/12
  EXPECT_LT(std::abs(correlation), 0.4);
}

TEST(LatinHypercubeTest, TheSameSeedGivesTheSamePointsAnotherSeedOthers) {
  const std::vector<SweepAxis> axes = {Lhs("/A=0:10"), Lhs("/Sim/Floor/Material=PVC,Wood,Carpet")};
  const std::vector<SweepPoint> first = LatinHypercube(axes, 30, 42);
  EXPECT_EQ(LatinHypercube(axes, 30, 42), first);
  const std::vector<SweepPoint> other = LatinHypercube(axes, 30, 43);
  EXPECT_NE(Values(other, 0), Values(first, 0));
  // Each axis has its own stream: adding an axis leaves the others' values as they were.
  const std::vector<SweepPoint> more = LatinHypercube({axes[0], axes[1], Lhs("/B=0:1")}, 30, 42);
  EXPECT_EQ(Values(more, 0), Values(first, 0));
}

TEST(LatinHypercubeTest, CategoriesAreStrataInEqualShares) {
  const std::vector<SweepPoint> points =
      LatinHypercube({Lhs("/Sim/Floor/Material=PVC,Wood,Carpet"), Lhs("/A=0:1")}, 10, 5);
  std::map<std::string, int> count;
  for (const SweepPoint& point : points) {
    const SweepValue& value = point[0].second;
    ASSERT_TRUE(value.categorical());
    const std::vector<std::string> names = {"PVC", "Wood", "Carpet"};
    EXPECT_EQ(names.at(static_cast<std::size_t>(value.number)), value.text);  // number = the category's index
    ++count[value.text];
  }
  EXPECT_EQ(count, (std::map<std::string, int>{{"Carpet", 3}, {"PVC", 4}, {"Wood", 3}}));
  EXPECT_TRUE(OnePerStratum(Values(points, 1), 0.0, 1.0));  // the numeric axis beside it is still stratified
}

TEST(LatinHypercubeTest, ADegenerateIntervalGivesItsOneValue) {
  for (double v : Values(LatinHypercube({Lhs("/A=2.5:2.5")}, 5, 1), 0)) EXPECT_EQ(v, 2.5);
}

TEST(LatinHypercubeTest, RejectsTooFewSamplesForTheCategoriesAPathTwiceAndBadCounts) {
  EXPECT_THAT(InputErrorOf([] { LatinHypercube({Lhs("/M=a,b,c")}, 2, 1); }),
              HasSubstr("2 samples cannot hold the 3 values of /M"));
  EXPECT_THAT(InputErrorOf([] {
                LatinHypercube({Lhs("/A=0:1"), Lhs("/A=0:2")}, 5, 1);
              }),
              HasSubstr("/A is swept twice"));
  EXPECT_THAT(InputErrorOf([] { LatinHypercube({Lhs("/A=0:1")}, 0, 1); }), HasSubstr("--samples"));
  EXPECT_THAT(InputErrorOf([] { LatinHypercube({Lhs("/A=0:1")}, 11, 1, 10); }), HasSubstr("expected 1 to 10"));
}

}  // namespace
}  // namespace orcs::batch
