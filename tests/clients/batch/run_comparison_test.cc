// `orcs-batch compare`'s reading and judging (clients/batch/run_comparison.h) on small results files written
// here; the whole command runs on real ODE and MuJoCo batches in tests/integration/orcs_batch_test.cc.
#include "clients/batch/run_comparison.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "model/core/error.h"
#include "tests/support/temp_dir.h"

namespace orcs::batch {
namespace {

using ::testing::HasSubstr;

constexpr const char* kA =
    R"({"id":"j0","status":"ok","fitness":1.0,"terms":{"distance":0.5,"energy":2.0}})" "\n"
    R"({"id":"j1","status":"ok","fitness":2.0,"terms":{"distance":0.7,"energy":1.0}})" "\n"
    R"({"id":"j2","status":"ok","fitness":3.0,"terms":{"distance":0.9}})" "\n";
constexpr const char* kB =
    R"({"id":"j1","status":"ok","fitness":2.0000001,"terms":{"distance":0.7,"energy":1.0}})" "\n"
    R"({"id":"j0","status":"ok","fitness":1.0,"terms":{"distance":0.5,"energy":2.0}})" "\n"
    R"({"id":"j2","status":"timeout","fitness":null,"terms":{}})" "\n"
    R"({"id":"j3","status":"ok","fitness":4.0,"terms":{}})" "\n";

class RunComparisonTest : public ::testing::Test {
 protected:
  test_support::TempDir dir_;
};

TEST_F(RunComparisonTest, MatchesJobsByIdAndTellsWhatChanged) {
  dir_.Write("a/results.jsonl", kA);
  const std::string b = dir_.Write("b.jsonl", kB);
  const RunComparison comparison = CompareRuns(dir_.PathOf("a"), b);  // a folder and a file
  EXPECT_EQ(comparison.a_path, dir_.PathOf("a/results.jsonl"));
  ASSERT_EQ(comparison.common.size(), 3u);
  EXPECT_EQ(comparison.common[0].job, "j0");  // A's order
  EXPECT_FALSE(Changed(comparison.common[0], 0.0));
  EXPECT_TRUE(Changed(comparison.common[1], 0.0));   // any bit
  EXPECT_FALSE(Changed(comparison.common[1], 1e-6));  // within the tolerance
  EXPECT_TRUE(Changed(comparison.common[2], 1e-6));   // ok → timeout, whatever the tolerance
  EXPECT_EQ(comparison.only_b, std::vector<std::string>{"j3"});
  EXPECT_TRUE(comparison.only_a.empty());
  EXPECT_EQ(comparison.terms, (std::vector<std::string>{"distance", "energy"}));

  const std::string text = ComparisonText(comparison, 0.0);
  EXPECT_THAT(text, HasSubstr("3 jobs in both (matched by job id), 2 changed (any bit); 0 only in A, 1 only in B"));
  EXPECT_THAT(text, HasSubstr("j1: fitness 2 → 2.0000001 (+1e-07);"));
  EXPECT_THAT(text, HasSubstr("j2: status ok → timeout; fitness 3 → —;"));
  EXPECT_THAT(text, HasSubstr("j3: only in B"));
  EXPECT_THAT(ComparisonText(comparison, 1e-6), HasSubstr("3 jobs in both (matched by job id), 1 changed by more than 1e-06"));
}

// A newcomer's paper cut (issue 52): ids are zero-padded by the batch's size, so the same seeds in an 8-job and a
// 16-job run shared no id ("0 jobs in both"). Jobs are matched by what they ran.
TEST_F(RunComparisonTest, TheSameSeedsInRunsOfDifferentSizesAreTheSameJobs) {
  const std::string eight = dir_.Write("eight.jsonl",
      R"({"id":"job-0","seed":11,"genome_index":0,"status":"ok","fitness":1.0})" "\n"
      R"({"id":"job-1","seed":12,"genome_index":0,"status":"ok","fitness":2.0})" "\n");
  const std::string sixteen = dir_.Write("sixteen.jsonl",
      R"({"id":"job-01","seed":12,"genome_index":0,"status":"ok","fitness":2.5})" "\n"
      R"({"id":"job-00","seed":11,"genome_index":0,"status":"ok","fitness":1.0})" "\n"
      R"({"id":"job-02","seed":13,"genome_index":0,"status":"ok","fitness":3.0})" "\n");
  const RunComparison comparison = CompareRuns(eight, sixteen);
  EXPECT_EQ(comparison.matched_by, "seed and genome");
  ASSERT_EQ(comparison.common.size(), 2u);
  EXPECT_EQ(comparison.common[0].job, "job-0 = job-00");
  EXPECT_FALSE(Changed(comparison.common[0], 0.0));
  EXPECT_EQ(comparison.common[1].job, "job-1 = job-01");
  EXPECT_TRUE(Changed(comparison.common[1], 0.0));
  EXPECT_EQ(comparison.only_b, std::vector<std::string>{"job-02"});
  EXPECT_THAT(ComparisonText(comparison, 0.0), HasSubstr("2 jobs in both (matched by seed and genome), 1 changed"));
  // Another genome with the same seed is another job.
  const std::string other = dir_.Write("other.jsonl",
      R"({"id":"job-0","seed":11,"genome_index":1,"status":"ok","fitness":1.0})" "\n");
  EXPECT_TRUE(CompareRuns(eight, other).common.empty());
}

TEST_F(RunComparisonTest, TheCsvHasEveryCommonJobWithItsDifferences) {
  const RunComparison comparison = CompareRuns(dir_.Write("a.jsonl", kA), dir_.Write("b.jsonl", kB));
  WriteComparisonCsv(dir_.PathOf("compare.csv"), comparison);
  const std::string csv = dir_.Read("compare.csv");
  EXPECT_THAT(csv, HasSubstr("job,status_a,status_b,fitness_a,fitness_b,fitness_delta,distance_a,distance_b,"
                             "distance_delta,energy_a,energy_b,energy_delta\n"));
  EXPECT_THAT(csv, HasSubstr("j0,ok,ok,1,1,0,0.5,0.5,0,2,2,0\n"));
  EXPECT_THAT(csv, HasSubstr("j2,ok,timeout,3,,,0.9,,,,,\n"));
}

TEST_F(RunComparisonTest, ABadLineIsNamedByFileAndLine) {
  const std::string a = dir_.Write("a.jsonl", kA);
  const auto problem = [&](const std::string& text) {
    try {
      CompareRuns(a, dir_.Write("b.jsonl", text));
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_THAT(problem("{\"id\":\"j0\",\"status\":\"ok\"}\nnot json\n"), HasSubstr("b.jsonl:2: not a JSON line"));
  EXPECT_THAT(problem("{\"status\":\"ok\"}\n"), HasSubstr("b.jsonl:1: \"id\": missing or not text"));
  EXPECT_THAT(problem("{\"id\":\"j0\",\"status\":\"ok\"}\n{\"id\":\"j0\",\"status\":\"ok\"}\n"),
              HasSubstr("b.jsonl:2: job 'j0' appears twice"));
  EXPECT_THAT(problem("{\"id\":\"j0\",\"status\":\"ok\",\"terms\":{\"d\":\"x\"}}\n"),
              HasSubstr("b.jsonl:1: \"terms\".d: not a number"));
  dir_.Write("empty/readme.txt", "");
  EXPECT_THROW(CompareRuns(a, dir_.PathOf("empty")), InputError);
}

}  // namespace
}  // namespace orcs::batch
