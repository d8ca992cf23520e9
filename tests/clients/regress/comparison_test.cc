// Comparing a case's result with its baseline: within tolerance or not, which terms moved, failed jobs, and the
// table and messages that say so.
#include "clients/regress/comparison.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "model/core/text.h"

namespace orcs::regress {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

SuiteCase ACase(double absolute, double relative) {
  SuiteCase entry;
  entry.name = "walk";
  entry.field = "cases[0]";
  entry.tolerance = Tolerance{absolute, relative};
  return entry;
}

// An ok result with two parameter sets, whose terms average to `distance` and `falls`.
v1::Result OkResult(double fitness, double distance, double falls) {
  v1::Result result;
  result.set_job_id("walk");
  result.set_status(v1::Result::OK);
  result.set_fitness(fitness);
  result.mutable_timings()->set_run_seconds(0.25);
  for (double offset : {-0.5, 0.5}) {
    v1::Result::ParameterSetResult* set = result.add_parameter_sets();
    set->set_status(v1::Result::OK);
    v1::Term* d = set->add_terms();
    d->set_name("distance");
    d->set_value(distance + offset);
    v1::Term* f = set->add_terms();
    f->set_name("falls");
    f->set_value(falls);
  }
  return result;
}

const BaselineCase kBaseline{"walk", "fnv1a64:0", 2.0, {{"distance", 1.0}, {"falls", 0.0}}};

TEST(ComparisonTest, PassesWithinTheAbsoluteToleranceAndFailsJustBeyondIt) {
  const SuiteCase entry = ACase(0.5, 0.0);
  const v1::Result inside_result = OkResult(2.5, 1.0, 0.0);
  const CaseComparison inside = CompareCase(entry, kBaseline, &inside_result);
  EXPECT_EQ(inside.verdict, Verdict::kPass) << "|2.5 − 2| = 0.5 is within 0.5";
  EXPECT_EQ(inside.difference, 0.5);
  EXPECT_EQ(inside.allowed, 0.5);
  EXPECT_TRUE(inside.passed());
  const v1::Result beyond_result = OkResult(std::nextafter(1.5, 0.0), 1.0, 0.0);
  const CaseComparison beyond = CompareCase(entry, kBaseline, &beyond_result);
  EXPECT_EQ(beyond.verdict, Verdict::kRegressed);
  EXPECT_FALSE(beyond.passed());
}

TEST(ComparisonTest, TheRelativeToleranceScalesWithTheBaseline) {
  const BaselineCase negative{"walk", "f", -200.0, {}};
  const v1::Result near = OkResult(-201.0, 1.0, 0.0);
  EXPECT_EQ(CompareCase(ACase(0.0, 0.01), negative, &near).verdict, Verdict::kPass) << "1 ≤ 0.01 · 200";
  EXPECT_EQ(CompareCase(ACase(0.0, 0.001), negative, &near).verdict, Verdict::kRegressed) << "1 > 0.001 · 200";
  EXPECT_EQ(CompareCase(ACase(1.0, 0.001), negative, &near).verdict, Verdict::kPass) << "the looser one counts";
}

TEST(ComparisonTest, ExactToleranceMeansTheSameBits) {
  const v1::Result same = OkResult(2.0, 1.0, 0.0);
  const v1::Result next = OkResult(std::nextafter(2.0, 3.0), 1.0, 0.0);
  EXPECT_EQ(CompareCase(ACase(0, 0), kBaseline, &same).verdict, Verdict::kPass);
  EXPECT_EQ(CompareCase(ACase(0, 0), kBaseline, &next).verdict, Verdict::kRegressed);
}

TEST(ComparisonTest, ListsTheTermsThatMovedWithBothValues) {
  const v1::Result result = OkResult(3.0, 1.25, 0.0);
  const CaseComparison comparison = CompareCase(ACase(0.1, 0), kBaseline, &result);
  ASSERT_EQ(comparison.moved.size(), 1u) << "falls did not move";
  EXPECT_EQ(comparison.moved[0].name, "distance");
  EXPECT_EQ(comparison.moved[0].baseline, 1.0);
  EXPECT_EQ(comparison.moved[0].now, 1.25) << "the mean over the sets";

  const BaselineCase other_terms{"walk", "f", 2.0, {{"distance", 1.25}, {"energy", 4.0}}};
  const CaseComparison renamed = CompareCase(ACase(0.1, 0), other_terms, &result);
  ASSERT_EQ(renamed.moved.size(), 2u);
  EXPECT_EQ(renamed.moved[0].name, "falls");
  EXPECT_TRUE(std::isnan(renamed.moved[0].baseline)) << "a term the baseline lacks";
  EXPECT_EQ(renamed.moved[1].name, "energy");
  EXPECT_TRUE(std::isnan(renamed.moved[1].now)) << "a term the result lacks";
}

TEST(ComparisonTest, AFailedJobOrAMissingResultFailsTheCase) {
  v1::Result timeout;
  timeout.set_job_id("walk");
  timeout.set_status(v1::Result::TIMEOUT);
  timeout.set_message("exceeded 5 s");
  const CaseComparison failed = CompareCase(ACase(1, 1), kBaseline, &timeout);
  EXPECT_EQ(failed.verdict, Verdict::kJobFailed);
  EXPECT_EQ(failed.status, "timeout");
  EXPECT_EQ(FailureMessage(failed), "case 'walk': the job did not run ok: timeout: exceeded 5 s; baseline fitness 2");
  EXPECT_EQ(FailureMessage(RecordCase(ACase(1, 1), &timeout)),
            "case 'walk': the job did not run ok: timeout: exceeded 5 s")
      << "no baseline while one is recorded";
  const CaseComparison missing = CompareCase(ACase(1, 1), kBaseline, nullptr);
  EXPECT_EQ(missing.verdict, Verdict::kNoResult);
  EXPECT_THAT(FailureMessage(missing), HasSubstr("no result"));
  EXPECT_FALSE(missing.passed());
}

TEST(ComparisonTest, TheFailureMessageHasEveryNumberInFull) {
  const double now = 2.0 + 1.0 / 3.0;
  const v1::Result result = OkResult(now, 1.0 / 7.0, 0.0);
  const CaseComparison comparison = CompareCase(ACase(0.001, 0), kBaseline, &result);
  ASSERT_EQ(comparison.verdict, Verdict::kRegressed);
  const std::string message = FailureMessage(comparison);
  EXPECT_THAT(message, HasSubstr("case 'walk' regressed: fitness baseline 2, measured " + text::FormatDouble(now) +
                                 ", difference " + text::FormatDouble(now - 2.0) + ", tolerance 0.001"));
  const double mean_distance = ((1.0 / 7.0 - 0.5) + (1.0 / 7.0 + 0.5)) / 2;  // as results.jsonl averages the sets
  EXPECT_THAT(message, HasSubstr("terms moved: distance 1 → " + text::FormatDouble(mean_distance)));
  EXPECT_THAT(message, Not(HasSubstr("falls")));
  EXPECT_EQ(FailureMessage(CompareCase(ACase(1, 0), kBaseline, &result)), "") << "a passing case";
}

TEST(ComparisonTest, TheTableHasARowPerCaseAndSaysWhyOneFailed) {
  const v1::Result ok = OkResult(2.0, 1.0, 0.0);
  const v1::Result off = OkResult(2.5, 1.0, 1.0);
  SuiteCase second = ACase(0.1, 0);
  second.name = "a-much-longer-case-name";
  const std::string table = ComparisonTable(
      {CompareCase(ACase(0.1, 0), kBaseline, &ok), CompareCase(second, kBaseline, &off), RecordCase(ACase(0, 0), &ok)});
  EXPECT_THAT(table, HasSubstr("case                     baseline"));
  EXPECT_THAT(table, ::testing::ContainsRegex("walk +2 +2 +0 +0.1 +PASS"));
  EXPECT_THAT(table, ::testing::ContainsRegex("a-much-longer-case-name +2 +2.5 +0.5 +0.1 +FAIL\n"));
  EXPECT_THAT(table, ::testing::ContainsRegex("walk +- +2 +- +- +RECORDED"));
  EXPECT_THAT(table, HasSubstr("  case 'a-much-longer-case-name' regressed: fitness baseline 2, measured 2.5"));
  EXPECT_THAT(table, HasSubstr("terms moved: falls 0 → 1"));
}

TEST(ComparisonTest, ABaselineEntryHoldsTheExactFitnessAndMeanTerms) {
  const v1::Result result = OkResult(0.1 + 0.2, 1.0 / 3.0, 2.0);
  const BaselineCase entry = BaselineOf("walk", "fnv1a64:1", result);
  EXPECT_EQ(entry.fitness, 0.1 + 0.2);
  ASSERT_EQ(entry.terms.size(), 2u);
  EXPECT_EQ(entry.terms[0].first, "distance");
  EXPECT_EQ(entry.terms[0].second, ((1.0 / 3.0 - 0.5) + (1.0 / 3.0 + 0.5)) / 2);
  EXPECT_EQ(entry.terms[1], (std::pair<std::string, double>("falls", 2.0)));
}

}  // namespace
}  // namespace orcs::regress
