// The sweep report: rows per grid point, the table and sweep.csv.
#include "clients/batch/sweep_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/support/temp_dir.h"

namespace orcs::batch {
using runtime::PlannedJob;
using runtime::SweepPoint;
namespace {

using ::testing::HasSubstr;

PlannedJob Planned(const std::string& id, std::size_t point) {
  PlannedJob planned;
  planned.job.set_job_id(id);
  planned.extra["point"] = point;
  return planned;
}

v1::Result Result(const std::string& id, double fitness, v1::Result::Status status = v1::Result::OK) {
  v1::Result result;
  result.set_job_id(id);
  result.set_fitness(fitness);
  result.set_status(status);
  return result;
}

class SweepReportTest : public ::testing::Test {
 protected:
  const std::vector<SweepAxis> axes_ = {ParseSweepAxis("/AngularMotor/PID/Proportional=10:20:2")};
  const std::vector<SweepPoint> points_ = SweepGrid(axes_);
  const std::vector<PlannedJob> jobs_ = {Planned("p0r0", 0), Planned("p0r1", 0), Planned("p1r0", 1),
                                         Planned("p1r1", 1)};
};

TEST_F(SweepReportTest, RowsAverageTheOkRepeatsOfEachPoint) {
  const std::vector<SweepRow> rows = SweepRows(
      points_, jobs_, {Result("p1r0", 4.0), Result("p0r0", 1.0), Result("p0r1", 3.0),
                       Result("p1r1", 100.0, v1::Result::TIMEOUT)});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].fitness, 2.0);
  EXPECT_EQ(rows[0].min_fitness, 1.0);
  EXPECT_EQ(rows[0].max_fitness, 3.0);
  EXPECT_EQ(rows[0].ok, 2);
  EXPECT_EQ(rows[1].fitness, 4.0);  // the timed-out repeat does not count
  EXPECT_EQ(rows[1].ok, 1);
  EXPECT_EQ(rows[1].jobs, 2);
}

TEST_F(SweepReportTest, APointWithoutOkRepeatsHasNoFitness) {
  const std::vector<SweepRow> rows = SweepRows(points_, jobs_, {Result("p0r0", 1.0)});
  EXPECT_TRUE(std::isnan(rows[1].fitness));
  const std::string table = SweepTable(axes_, rows);
  EXPECT_THAT(table, HasSubstr("PID/Proportional"));
  EXPECT_THAT(table, HasSubstr("0/2"));
}

TEST_F(SweepReportTest, WritesACsvThatReadsBack) {
  test_support::TempDir dir;
  const std::vector<SweepRow> rows = SweepRows(points_, jobs_, {Result("p0r0", 0.1 + 0.2), Result("p0r1", 0.1 + 0.2)});
  WriteSweepCsv(dir.path().string(), axes_, rows);
  std::ifstream in(dir.path() / "sweep.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(),
            "/AngularMotor/PID/Proportional,fitness,min_fitness,max_fitness,ok,jobs\n"
            "10,0.30000000000000004,0.30000000000000004,0.30000000000000004,2,2\n"
            "20,,,,0,2\n");
}

TEST(SweepReportCategoriesTest, CategoriesAppearByNameInTheTableAndTheCsv) {
  test_support::TempDir dir;
  const std::vector<SweepAxis> axes = {ParseSweepAxis("/Sim/Floor/Material=Wood,Carpet")};
  const std::vector<SweepRow> rows =
      SweepRows(SweepGrid(axes), {Planned("p0", 0), Planned("p1", 1)}, {Result("p0", 0.5), Result("p1", -1.0)});
  EXPECT_THAT(SweepTable(axes, rows), HasSubstr("Carpet"));
  WriteSweepCsv(dir.path().string(), axes, rows);
  EXPECT_EQ(dir.Read("sweep.csv"),
            "/Sim/Floor/Material,fitness,min_fitness,max_fitness,ok,jobs\n"
            "Wood,0.5,0.5,0.5,1,1\n"
            "Carpet,-1,-1,-1,1,1\n");
}

}  // namespace
}  // namespace orcs::batch
