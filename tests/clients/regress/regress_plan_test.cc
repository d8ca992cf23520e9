// `orcs-batch regress` before and after its batch, without processes: the plan (jobs, fingerprints, --set, the
// baseline's checks) and the report (exit codes, the baseline recorded, the JUnit file) from made-up results.
#include "clients/regress/regress_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <filesystem>
#include <sstream>

#include "clients/regress/job_fingerprint.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::regress {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::HasSubstr;

// The pendulum rig replaying a quarter turn: a world that builds in no time.
constexpr const char* kEnvironment = R"(<ORCS version="1.0"><Agent><Pendulum name="Pendulum"/></Agent></ORCS>)";
constexpr const char* kRecord = "# layout: raw\n0,90,1\n500,0,1\n";
constexpr const char* kScenario = R"({
  "environment": "rig.xml", "agent": "Pendulum", "duration": 0.05,
  "controller": {"type": "keyframes", "record": "quarter.csv"},
  "fitness": {"terms": [{"type": "tracking_error", "record": "quarter.csv"}, {"type": "energy"}]}
})";
constexpr const char* kSuite = R"({"name": "rig", "cases": [
  {"name": "plain", "scenario": "rig.json"},
  {"name": "weak", "scenario": "rig.json", "seed": 5, "values": {"/AngularMotor/FMaxFactor": 0.5}}]})";

class RegressPlanTest : public ::testing::Test {
 protected:
  RegressPlanTest() {
    dir_.Write("rig.xml", kEnvironment);
    dir_.Write("quarter.csv", kRecord);
    dir_.Write("rig.json", kScenario);
    options_.suite = dir_.Write("suite.json", kSuite);
  }
  RegressPlan Plan() { return PlanRegression(options_, notes_); }
  std::string PlanError() {
    return InputErrorOf([&] { Plan(); });
  }
  // Records a baseline for the suite as it is now, from made-up fitness values 1, 2, ...
  void RecordBaseline() {
    options_.update_baseline = true;
    const RegressPlan plan = Plan();
    std::ostringstream out;
    ASSERT_EQ(ReportRegression(plan, Summary(plan, {1.0, 2.0}), "r.jsonl", out), 0) << out.str();
    options_.update_baseline = false;
  }
  // A summary with one ok result per case, fitness and a term from `fitness`.
  static runtime::BatchSummary Summary(const RegressPlan& plan, const std::vector<double>& fitness) {
    runtime::BatchSummary summary;
    summary.seconds = 2.0;
    for (std::size_t i = 0; i < fitness.size(); ++i) {
      v1::Result result;
      result.set_job_id(plan.jobs.at(i).job.job_id());
      result.set_status(v1::Result::OK);
      result.set_fitness(fitness[i]);
      v1::Term* term = result.add_parameter_sets()->add_terms();
      term->set_name("tracking_error");
      term->set_value(-fitness[i]);
      summary.results.push_back(result);
    }
    return summary;
  }
  TempDir dir_;
  batch::BatchOptions options_;
  std::ostringstream notes_;
};

TEST_F(RegressPlanTest, PlansOneJobPerCaseNamedAfterItWithItsSeedAndValues) {
  options_.update_baseline = true;
  const RegressPlan plan = Plan();
  ASSERT_EQ(plan.jobs.size(), 2u);
  EXPECT_EQ(plan.jobs[0].job.job_id(), "plain");
  EXPECT_EQ(plan.jobs[0].job.seed(), 1u);
  EXPECT_EQ(plan.jobs[0].job.overrides_size(), 0);
  EXPECT_EQ(plan.jobs[0].extra["case"], "plain");
  EXPECT_THAT(plan.jobs[0].job.scenario_json(), HasSubstr("<Pendulum")) << "files inlined";
  const v1::Job& weak = plan.jobs[1].job;
  EXPECT_EQ(weak.job_id(), "weak");
  EXPECT_EQ(weak.seed(), 5u);
  ASSERT_EQ(weak.overrides_size(), 1);
  EXPECT_EQ(weak.overrides(0).path(), "/AngularMotor/FMaxFactor");
  EXPECT_EQ(weak.overrides(0).value(), "0.5");
  ASSERT_EQ(plan.fingerprints.size(), 2u);
  EXPECT_EQ(plan.fingerprints[1], JobFingerprint(weak));
  EXPECT_NE(plan.fingerprints[0], plan.fingerprints[1]);
  EXPECT_EQ(plan.baseline_path, dir_.PathOf("suite.baseline.json"));
}

TEST_F(RegressPlanTest, SetOverridesEveryCaseLastAndIsNotPartOfTheFingerprint) {
  RecordBaseline();
  const RegressPlan before = Plan();
  options_.sets = {"/AngularMotor/FMaxFactor=0.7", "/AngularMotor/PID/Proportional = 12"};
  const RegressPlan after = Plan();  // the baseline still matches
  EXPECT_EQ(after.fingerprints, before.fingerprints);
  const v1::Job& weak = after.jobs[1].job;
  ASSERT_EQ(weak.overrides_size(), 3);
  EXPECT_EQ(weak.overrides(0).value(), "0.5") << "the case's own value first";
  EXPECT_EQ(weak.overrides(1).path(), "/AngularMotor/FMaxFactor");
  EXPECT_EQ(weak.overrides(1).value(), "0.7") << "then --set, which wins";
  EXPECT_EQ(weak.overrides(2).path(), "/AngularMotor/PID/Proportional");
  EXPECT_EQ(weak.overrides(2).value(), "12");
  EXPECT_EQ(after.jobs[0].job.overrides_size(), 2);
  EXPECT_EQ(notes_.str(), "");
}

TEST_F(RegressPlanTest, BadSetOptionsAreErrorsNamingTheOption) {
  EXPECT_THAT(InputErrorOf([] { ParseSetOption("/a/b"); }), HasSubstr("--set '/a/b': expected PATH=VALUE"));
  EXPECT_THAT(InputErrorOf([] { ParseSetOption("a/b=1"); }), HasSubstr("--set 'a/b=1': expected a repository path"));
  EXPECT_THAT(InputErrorOf([] { ParseSetOption("/a/b= "); }), HasSubstr("--set '/a/b= ': expected a value"));
  options_.update_baseline = true;
  options_.sets = {"/AngularMotor/FMaxFactor=0.7"};
  EXPECT_THAT(PlanError(), HasSubstr("--set: cannot be combined with --update-baseline"));
  options_.sets.clear();
  RecordBaseline();
  options_.sets = {"/AngularMotor/NoSuchValue=1"};
  const std::string error = PlanError();
  EXPECT_THAT(error, HasSubstr("suite.json: case 'plain' (cases[0]): "));
  EXPECT_THAT(error, HasSubstr("/AngularMotor/NoSuchValue"));
}

TEST_F(RegressPlanTest, AMissingBaselineIsAnErrorUnlessOneIsRecorded) {
  EXPECT_THAT(PlanError(), HasSubstr("suite.baseline.json: no baseline here; record one with --update-baseline"));
  options_.baseline = dir_.PathOf("elsewhere.json");
  EXPECT_THAT(PlanError(), HasSubstr("elsewhere.json: no baseline here"));
}

TEST_F(RegressPlanTest, ACaseWhoseValuesChangedNoLongerMatchesItsBaseline) {
  RecordBaseline();
  EXPECT_NO_THROW(Plan());
  dir_.Write("suite.json", std::string(kSuite).replace(std::string(kSuite).find("0.5"), 3, "0.6"));
  const std::string error = PlanError();
  EXPECT_THAT(error, HasSubstr("suite.baseline.json: field 'cases.weak.fingerprint' expected fnv1a64:"));
  EXPECT_THAT(error, HasSubstr("run with --update-baseline if the change is intended"));
}

TEST_F(RegressPlanTest, ACaseWithAValueTheWorldLacksIsAnErrorNamingTheCase) {
  dir_.Write("suite.json", R"({"cases": [{"name": "odd", "scenario": "rig.json", "values": {"/Nowhere": 1}}]})");
  options_.update_baseline = true;
  const std::string error = PlanError();
  EXPECT_THAT(error, HasSubstr("suite.json: case 'odd' (cases[0]): "));
  EXPECT_THAT(error, HasSubstr("/Nowhere"));
}

TEST_F(RegressPlanTest, NotesACaseWhoseRandomisationDrawsASetPathAnew) {
  std::string drawn = kScenario;
  drawn.replace(drawn.rfind('}'), 1,
                R"(, "randomisation": {"parameters": [{"path": "/AngularMotor/FMaxFactor", "uniform": [0.8, 0.9]}]}})");
  dir_.Write("rig.json", drawn);
  RecordBaseline();
  options_.sets = {"/AngularMotor/FMaxFactor=0.7"};
  Plan();
  EXPECT_THAT(notes_.str(), HasSubstr("note: case 'plain' draws /AngularMotor/FMaxFactor anew for every parameter "
                                      "set (randomisation.parameters[0] of "));
  EXPECT_THAT(notes_.str(), HasSubstr("case 'weak'"));
}

TEST_F(RegressPlanTest, ReportsPassAndRegressionWithExitCodesAndJUnit) {
  RecordBaseline();
  options_.junit = dir_.PathOf("junit.xml");
  const RegressPlan plan = Plan();
  std::ostringstream same;
  EXPECT_EQ(ReportRegression(plan, Summary(plan, {1.0, 2.0}), "r.jsonl", same), 0) << same.str();
  EXPECT_THAT(same.str(), HasSubstr("orcs-batch regress: 2 cases: 2 pass, 0 regressed, 0 failed jobs in 2.00 s"));
  std::ostringstream moved;
  EXPECT_EQ(ReportRegression(plan, Summary(plan, {1.0, 2.5}), "r.jsonl", moved), 1);
  EXPECT_THAT(moved.str(), HasSubstr("1 pass, 1 regressed"));
  EXPECT_THAT(moved.str(), HasSubstr("case 'weak' regressed: fitness baseline 2, measured 2.5, difference 0.5, "
                                     "tolerance 0; terms moved: tracking_error -2 → -2.5"));
  tinyxml2::XMLDocument junit;
  ASSERT_EQ(junit.LoadFile(options_.junit.c_str()), tinyxml2::XML_SUCCESS);
  EXPECT_EQ(junit.FirstChildElement("testsuites")->IntAttribute("failures"), 1);
  std::ostringstream missing;
  EXPECT_EQ(ReportRegression(plan, Summary(plan, {1.0}), "r.jsonl", missing), 1) << "no result for 'weak'";
  EXPECT_THAT(missing.str(), HasSubstr("1 without result"));
}

TEST_F(RegressPlanTest, RecordsTheBaselineOnlyWhenEveryCaseRanOk) {
  options_.update_baseline = true;
  const RegressPlan plan = Plan();
  runtime::BatchSummary summary = Summary(plan, {1.0, 2.0});
  summary.results[1].set_status(v1::Result::UNSTABLE_PHYSICS);
  std::ostringstream failed;
  EXPECT_EQ(ReportRegression(plan, summary, "r.jsonl", failed), 1);
  EXPECT_THAT(failed.str(), HasSubstr("baseline not written"));
  EXPECT_FALSE(std::filesystem::exists(plan.baseline_path));
  std::ostringstream ok;
  EXPECT_EQ(ReportRegression(plan, Summary(plan, {1.0, 2.0}), "r.jsonl", ok), 0);
  EXPECT_THAT(ok.str(), HasSubstr("baseline of 2 cases written to " + plan.baseline_path));
  const Baseline written = ReadBaseline(plan.baseline_path);
  EXPECT_EQ(written.suite, "rig");
  EXPECT_EQ(written.Find("weak")->fitness, 2.0);
  EXPECT_EQ(written.Find("weak")->fingerprint, plan.fingerprints[1]);
}

}  // namespace
}  // namespace orcs::regress
