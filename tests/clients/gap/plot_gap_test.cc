// scripts/plot_gap.py on a tiny report folder written here (report.json and the traces of two channels over two
// runs): both plots are drawn, and a missing or malformed input is exit 2 naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using test_support::ProcessResult;
using test_support::RunProcess;
using ::testing::HasSubstr;

constexpr const char* kHeader =
    "time,measured,before,refit,after,desired,velocity,speed,acceleration,load,command_error";

// A 1 Hz, 20° sine with a backlash-like error near reversals that `refit` lacks and `after` has; `after` is
// left empty when `with_after` is false (no effect won).
std::string TraceCsv(bool with_after, double phase) {
  std::ostringstream csv;
  csv << kHeader << "\n";
  for (int k = 0; k < 200; ++k) {
    const double t = k * 0.01;
    const double x = 20.0 * std::sin(2 * std::numbers::pi * t + phase);
    const double v = 40.0 * std::numbers::pi * std::cos(2 * std::numbers::pi * t + phase);
    const double backlash = 0.6 * std::copysign(1.0, v) * std::exp(-std::abs(v) / 20.0);
    const double measured = x + backlash;
    csv << t << "," << measured << "," << 0.9 * x << "," << x << ",";
    if (with_after) csv << x + 0.9 * backlash;
    csv << "," << x << "," << v << "," << std::abs(v) << ",0,0.1," << x - measured << "\n";
  }
  return csv.str();
}

class PlotGapScriptTest : public ::testing::Test {
 protected:
  void WriteReport(const std::string& effect, const std::string& quantity) {
    dir_.Write("report/report.json", R"({"rig": "pendulum", "verdict": {"effect": )" + effect +
                                         R"(, "text": "a test verdict", "quantity": ")" + quantity +
                                         R"("}, "worst_channels": ["Right/Knee", "Left/Hip"]})");
  }
  void WriteTraces(bool with_after) {
    for (const char* run : {"run1", "run2"}) {
      dir_.Write(std::string("report/traces/") + run + ".Right_Knee.csv", TraceCsv(with_after, 0.0));
      dir_.Write(std::string("report/traces/") + run + ".Left_Hip.csv", TraceCsv(with_after, 1.0));
    }
  }
  ProcessResult Plot() {
    return RunProcess({"/usr/bin/python3", ORCS_SOURCE_DIR "/scripts/plot_gap.py", dir_.PathOf("report")});
  }
  void ExpectPng(const std::string& relative_name) {
    const std::string png = dir_.Read("report/plots/" + relative_name);
    ASSERT_GT(png.size(), 1000u) << relative_name;
    EXPECT_EQ(png.substr(1, 3), "PNG") << relative_name;
  }

  test_support::TempDir dir_;
};

TEST_F(PlotGapScriptTest, DrawsTheWorstChannelsAndTheResidualAgainstTheVerdictsQuantity) {
  WriteReport(R"("Backlash")", "velocity");
  WriteTraces(true);
  const ProcessResult plot = Plot();
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  ExpectPng("worst_channels.png");
  ExpectPng("residual_vs_velocity.png");
  EXPECT_THAT(plot.out, HasSubstr("residual_vs_velocity.png"));
}

TEST_F(PlotGapScriptTest, WithoutAnEffectPlotsTheResidualAgainstSpeed) {
  WriteReport("null", "velocity");
  WriteTraces(false);
  const ProcessResult plot = Plot();
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  ExpectPng("worst_channels.png");
  ExpectPng("residual_vs_speed.png");
  EXPECT_EQ(dir_.Read("report/plots/residual_vs_velocity.png"), "");
}

TEST_F(PlotGapScriptTest, AMissingReportIsExit2NamingTheFile) {
  WriteTraces(true);
  const ProcessResult plot = Plot();
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_THAT(plot.err, HasSubstr(dir_.PathOf("report/report.json")));
  EXPECT_EQ(std::count(plot.err.begin(), plot.err.end(), '\n'), 1) << plot.err;  // one line, no traceback
}

TEST_F(PlotGapScriptTest, MissingOrMalformedTracesAreExit2NamingTheFile) {
  WriteReport(R"("Backlash")", "velocity");
  ProcessResult plot = Plot();
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_THAT(plot.err, HasSubstr("Right_Knee.csv: no trace of worst channel Right/Knee"));
  WriteTraces(true);
  dir_.Write("report/traces/run2.Left_Hip.csv", std::string(kHeader) + "\n0,1,2,3,4,5,6,7,8,9,10\n0.01,x,2,3,,,,,,,\n");
  plot = Plot();
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_THAT(plot.err, HasSubstr("run2.Left_Hip.csv:3: column measured: expected a number, found 'x'"));
  dir_.Write("report/report.json", R"({"verdict": {"effect": "Backlash", "quantity": "velocity"}})");
  plot = Plot();
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_THAT(plot.err, HasSubstr("report.json: expected \"worst_channels\""));
}

}  // namespace
}  // namespace orcs
