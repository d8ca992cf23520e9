// The binned first-order sensitivity index on data whose answer is known: hand-computed cases, a strong and a weak
// input, an input without effect, a linear output, categories and grid values with ties.
#include "clients/batch/sensitivity.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "clients/batch/latin_hypercube.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

std::vector<SweepValue> Numbers(const std::vector<double>& values) { return {values.begin(), values.end()}; }

// A Latin hypercube over three inputs in [0, 1]: independent, evenly spread samples.
std::vector<std::vector<SweepValue>> Inputs(int samples, std::uint64_t seed) {
  const std::vector<SweepAxis> axes = {ParseSweepAxis("/X1=0:1", SweepSampling::kLatinHypercube),
                                       ParseSweepAxis("/X2=0:1", SweepSampling::kLatinHypercube),
                                       ParseSweepAxis("/X3=0:1", SweepSampling::kLatinHypercube)};
  std::vector<std::vector<SweepValue>> x(3);
  for (const SweepPoint& point : LatinHypercube(axes, samples, seed)) {
    for (std::size_t a = 0; a < 3; ++a) x[a].push_back(point[a].second);
  }
  return x;
}

TEST(SensitivityTest, HandComputedCases) {
  // Bins {0, 1} and {2, 3}: means 0 and 1 around 0.5 explain all of the variance, or none of it.
  const Sensitivity all = FirstOrderSensitivity(Numbers({0, 1, 2, 3}), {0, 0, 1, 1}, 2);
  EXPECT_DOUBLE_EQ(all.index, 1.0);
  ASSERT_EQ(all.bins.size(), 2u);
  EXPECT_EQ(all.bins[0].count, 2);
  EXPECT_EQ(all.bins[0].mean, 0.0);
  EXPECT_EQ(all.bins[1].mean, 1.0);
  EXPECT_EQ(all.bins[1].label, "2..3");
  // Mean 1/3 under no effect, variance 2·1·2/(3²·5): the noise floor is 1/3 + 2·√(4/45).
  EXPECT_DOUBLE_EQ(all.noise_floor, 1.0 / 3.0 + 2 * std::sqrt(4.0 / 45.0));
  EXPECT_DOUBLE_EQ(FirstOrderSensitivity(Numbers({0, 1, 2, 3}), {0, 1, 0, 1}, 2).index, 0.0);
  // Bins {0, 1} (mean 1) and {2, 3} (mean 3) around 2: between 2·1² + 2·1² = 4, total 2² + 2² = 8 → 0.5.
  EXPECT_DOUBLE_EQ(FirstOrderSensitivity(Numbers({3, 0, 2, 1}), {4, 0, 2, 2}, 2).index, 0.5);
}

TEST(SensitivityTest, AStrongInputFarOutranksAWeakOne) {
  const std::vector<std::vector<SweepValue>> x = Inputs(400, 1);
  std::vector<double> y;
  for (std::size_t i = 0; i < 400; ++i)
    y.push_back(std::sin(2 * std::numbers::pi * x[0][i].number) + 0.1 * x[1][i].number);
  const int bins = DefaultBinCount(y.size());
  EXPECT_EQ(bins, 20);
  const double s1 = FirstOrderSensitivity(x[0], y, bins).index;
  const double s2 = FirstOrderSensitivity(x[1], y, bins).index;
  // Var f = 1/2, Var g = 0.01/12: S1 ≈ 0.998, S2 ≈ 0.002 plus the 19/399 ≈ 0.048 that 20 bins give any input.
  EXPECT_GT(s1, 0.95);
  EXPECT_LT(s2, 0.15);
  EXPECT_GT(s1, 8 * s2);
}

TEST(SensitivityTest, AnInputWithoutEffectScoresAboutItsNoiseFloor) {
  const std::vector<std::vector<SweepValue>> x = Inputs(2000, 2);
  std::vector<double> y;
  for (std::size_t i = 0; i < 2000; ++i) y.push_back(x[0][i].number + x[1][i].number * x[1][i].number);
  const Sensitivity none = FirstOrderSensitivity(x[2], y, DefaultBinCount(y.size()));
  // 45 bins: mean 44/1999 = 0.022 under no effect, standard deviation √(2·44·1955/(1999²·2001)) = 0.0046.
  EXPECT_NEAR(none.noise_floor, 44.0 / 1999.0 + 2 * std::sqrt(2.0 * 44 * 1955 / (1999.0 * 1999 * 2001)), 1e-15);
  EXPECT_LT(none.index, 0.05);
  EXPECT_LT(none.index, none.noise_floor);
  EXPECT_GT(FirstOrderSensitivity(x[0], y, 45).index, 10 * none.noise_floor);  // the input that matters clears it
}

TEST(SensitivityTest, ALinearOutputOfOneUniformInputApproachesOne) {
  for (const auto& [samples, least] : {std::pair{16, 0.85}, std::pair{400, 0.99}}) {
    const std::vector<std::vector<SweepValue>> x = Inputs(samples, 3);
    std::vector<double> y;
    for (const SweepValue& v : x[0]) y.push_back(3.0 * v.number - 1.0);
    // Within-bin variance is (1/B)² of the total: S = 1 − 1/B² (16 → 0.9375, 400 → 0.9975).
    EXPECT_GT(FirstOrderSensitivity(x[0], y, DefaultBinCount(y.size())).index, least) << samples;
  }
}

TEST(SensitivityTest, CategoriesAreTheirOwnBins) {
  std::vector<SweepValue> x;
  std::vector<double> y;
  const std::vector<std::string> names = {"PVC", "Wood", "Carpet"};
  for (int i = 0; i < 30; ++i) {
    x.emplace_back(names[static_cast<std::size_t>(i % 3)], i % 3);
    y.push_back((i % 3) * 10.0 + (i % 2 == 0 ? 0.5 : -0.5));
  }
  const Sensitivity s = FirstOrderSensitivity(x, y, 1);  // the bin count is for numbers only
  ASSERT_EQ(s.bins.size(), 3u);
  EXPECT_EQ(s.bins[0].label, "PVC");
  EXPECT_EQ(s.bins[2].label, "Carpet");
  EXPECT_EQ(s.bins[1].count, 10);
  EXPECT_NEAR(s.bins[1].mean, 10.0, 0.1);
  EXPECT_GT(s.index, 0.99);
}

TEST(SensitivityTest, EqualValuesNeverStraddleTwoBins) {
  const std::vector<SweepValue> x = Numbers({1, 2, 3, 1, 2, 3, 1, 2, 3});
  const std::vector<double> y = {1, 2, 3, 1, 2, 3, 1, 2, 3};
  const Sensitivity three = FirstOrderSensitivity(x, y, 3);  // a grid axis: one bin per value
  ASSERT_EQ(three.bins.size(), 3u);
  EXPECT_EQ(three.bins[1].label, "2");
  EXPECT_EQ(three.bins[1].count, 3);
  EXPECT_DOUBLE_EQ(three.index, 1.0);
  const Sensitivity two = FirstOrderSensitivity(x, y, 2);  // 4.5 per bin would split the 2s: they stay together
  ASSERT_EQ(two.bins.size(), 2u);
  EXPECT_EQ(two.bins[0].count, 6);
  EXPECT_EQ(two.bins[1].count, 3);
}

TEST(SensitivityTest, AConstantOutputHasNoIndexAndLengthsMustAgree) {
  EXPECT_TRUE(std::isnan(FirstOrderSensitivity(Numbers({1, 2, 3}), {0.1, 0.1, 0.1}, 2).index));
  EXPECT_TRUE(std::isnan(FirstOrderSensitivity({}, {}, 2).index));
  EXPECT_THROW(FirstOrderSensitivity(Numbers({1, 2}), {1.0}, 2), std::invalid_argument);
}

}  // namespace
}  // namespace orcs::batch
