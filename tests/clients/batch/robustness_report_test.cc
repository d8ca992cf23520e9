// The robustness report: the fitness distribution over a sweep's points, the worst point, the sensitivity ranking,
// and the files robustness.json and robustness.md.
#include "clients/batch/robustness_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "tests/support/temp_dir.h"

namespace orcs::batch {
using runtime::SweepValue;
namespace {

using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

SweepRow Row(double gain, const std::string& floor, int floor_index, double fitness, int ok = 1) {
  SweepRow row;
  row.point = {{"/AngularMotor/PID/Proportional", gain}, {"/Sim/Floor/Material", SweepValue(floor, floor_index)}};
  row.jobs = 1;
  row.ok = ok;
  row.fitness = row.min_fitness = row.max_fitness = ok > 0 ? fitness : kNaN;
  return row;
}

class RobustnessReportTest : public ::testing::Test {
 protected:
  const std::vector<SweepAxis> axes_ = {
      ParseSweepAxis("/AngularMotor/PID/Proportional=10:30", SweepSampling::kLatinHypercube),
      ParseSweepAxis("/Sim/Floor/Material=PVC,Light", SweepSampling::kLatinHypercube)};
  // The floor decides the fitness (PVC ≈ 1, Light ≈ −1); the gain barely matters. Point 5 did not run ok.
  const std::vector<SweepRow> rows_ = {Row(12, "PVC", 0, 1.0),    Row(14, "Light", 1, -1.0), Row(18, "PVC", 0, 1.1),
                                       Row(22, "Light", 1, -1.2), Row(26, "PVC", 0, 0.9),    Row(29, "Light", 1, 0, 0),
                                       Row(28, "Light", 1, -0.9)};
};

TEST_F(RobustnessReportTest, DescribesTheFitnessOfThePointsThatRanOk) {
  const RobustnessReport report = MakeRobustnessReport("hips", SweepSampling::kLatinHypercube, axes_, rows_);
  const FitnessDistribution& d = report.fitness;
  EXPECT_EQ(d.points, 7);
  EXPECT_EQ(d.ok_points, 6);
  EXPECT_NEAR(d.mean, (1.0 - 1.0 + 1.1 - 1.2 + 0.9 - 0.9) / 6, 1e-15);
  EXPECT_EQ(d.min, -1.2);
  EXPECT_EQ(d.max, 1.1);
  // Sorted: −1.2 −1 −0.9 0.9 1 1.1; the median interpolates halfway between −0.9 and 0.9; q1 at position 1.25.
  EXPECT_NEAR(d.median, 0.0, 1e-15);
  EXPECT_NEAR(d.q1, -1.0 + 0.25 * 0.1, 1e-12);
  double squares = 0.0;
  for (double f : {1.0, -1.0, 1.1, -1.2, 0.9, -0.9}) squares += (f - d.mean) * (f - d.mean);
  EXPECT_NEAR(d.deviation, std::sqrt(squares / 5), 1e-12);
  ASSERT_TRUE(report.worst.has_value());
  EXPECT_EQ(*report.worst, 3u);
}

TEST_F(RobustnessReportTest, RanksTheFloorAboveTheGain) {
  const RobustnessReport report = MakeRobustnessReport("hips", SweepSampling::kLatinHypercube, axes_, rows_);
  ASSERT_EQ(report.parameters.size(), 2u);
  EXPECT_TRUE(report.parameters[1].categorical);
  EXPECT_GT(report.parameters[1].sensitivity.index, 0.95);
  EXPECT_EQ(report.ranking, (std::vector<std::size_t>{1, 0}));
  EXPECT_THAT(RankingText(report), HasSubstr("most sensitive to /Sim/Floor/Material (S 0.9"));
  EXPECT_THAT(RankingText(report), HasSubstr(", then /AngularMotor/PID/Proportional (S "));
  const std::string summary = RobustnessSummary(report, rows_);
  EXPECT_THAT(summary, HasSubstr("fitness over 6 of 7 points"));
  EXPECT_THAT(summary, HasSubstr("worst point 3 (/AngularMotor/PID/Proportional=22, /Sim/Floor/Material=Light)"));
}

TEST_F(RobustnessReportTest, WritesJsonAndMarkdown) {
  test_support::TempDir dir;
  const RobustnessReport report = MakeRobustnessReport("hips", SweepSampling::kLatinHypercube, axes_, rows_);
  WriteRobustnessReport(dir.path().string(), report, rows_);
  const nlohmann::json json = nlohmann::json::parse(dir.Read("robustness.json"));
  EXPECT_EQ(json["sampling"], "lhs");
  EXPECT_EQ(json["points"], 7);
  EXPECT_EQ(json["ok_points"], 6);
  EXPECT_EQ(json["fitness"]["min"], -1.2);
  EXPECT_EQ(json["worst"]["point"], 3);
  EXPECT_EQ(json["worst"]["params"]["/Sim/Floor/Material"], "Light");
  EXPECT_EQ(json["worst"]["params"]["/AngularMotor/PID/Proportional"], 22.0);
  ASSERT_EQ(json["sensitivity"].size(), 2u);
  EXPECT_EQ(json["sensitivity"][1]["kind"], "categorical");
  EXPECT_EQ(json["sensitivity"][1]["bins"][1]["label"], "Light");
  EXPECT_EQ(json["sensitivity"][1]["bins"][1]["count"], 3);
  EXPECT_NEAR(json["sensitivity"][1]["bins"][1]["mean"].get<double>(), (-1.0 - 1.2 - 0.9) / 3, 1e-15);
  EXPECT_EQ(json["ranking"], nlohmann::json::parse(R"(["/Sim/Floor/Material", "/AngularMotor/PID/Proportional"])"));
  const std::string md = dir.Read("robustness.md");
  EXPECT_THAT(md, HasSubstr("# Robustness: hips"));
  EXPECT_THAT(md, HasSubstr("| 1 | `/Sim/Floor/Material` |"));
  EXPECT_THAT(md, HasSubstr("| Light | 3 | -1.033 |"));
  EXPECT_THAT(md, HasSubstr("Fitness most sensitive to /Sim/Floor/Material"));
}

TEST_F(RobustnessReportTest, NoOkPointOrNoVariationIsSaidPlainly) {
  const std::vector<SweepRow> failed = {Row(12, "PVC", 0, 0, 0), Row(14, "Light", 1, 0, 0)};
  const RobustnessReport none = MakeRobustnessReport("hips", SweepSampling::kGrid, axes_, failed);
  EXPECT_EQ(none.fitness.ok_points, 0);
  EXPECT_TRUE(std::isnan(none.fitness.mean));
  EXPECT_FALSE(none.worst.has_value());
  EXPECT_THAT(RankingText(none), HasSubstr("did not vary"));
  test_support::TempDir dir;
  WriteRobustnessReport(dir.path().string(), none, failed);
  const nlohmann::json json = nlohmann::json::parse(dir.Read("robustness.json"));
  EXPECT_TRUE(json["fitness"]["mean"].is_null());
  EXPECT_TRUE(json["worst"].is_null());
  EXPECT_TRUE(json["sensitivity"][0]["index"].is_null());

  const std::vector<SweepRow> flat = {Row(12, "PVC", 0, 0.5), Row(14, "Light", 1, 0.5), Row(20, "PVC", 0, 0.5)};
  EXPECT_THAT(RankingText(MakeRobustnessReport("hips", SweepSampling::kGrid, axes_, flat)), HasSubstr("did not vary"));
}

}  // namespace
}  // namespace orcs::batch
