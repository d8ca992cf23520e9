// Job fingerprints: the same for the same job, different when anything that decides its result changes.
#include "clients/regress/job_fingerprint.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>

namespace orcs::regress {
namespace {

v1::Job AJob() {
  v1::Job job;
  job.set_job_id("a");
  job.set_scenario_json(R"({"duration":1})");
  job.set_genome_json("[1,2]");
  job.set_seed(3);
  v1::Override* override = job.add_overrides();
  override->set_path("/AngularMotor/FMaxFactor");
  override->set_value("0.9");
  return job;
}

TEST(JobFingerprintTest, IsSixteenHexDigitsAndTheSameForTheSameJob) {
  const std::string fingerprint = JobFingerprint(AJob());
  EXPECT_THAT(fingerprint, ::testing::MatchesRegex("fnv1a64:[0-9a-f]{16}"));
  EXPECT_EQ(JobFingerprint(AJob()), fingerprint);
}

TEST(JobFingerprintTest, IgnoresTheJobIdBatchAndTimeLimit) {
  v1::Job job = AJob();
  job.set_job_id("b");
  job.set_batch_id("batch");
  job.set_time_limit_seconds(5);
  EXPECT_EQ(JobFingerprint(job), JobFingerprint(AJob()));
}

TEST(JobFingerprintTest, ChangesWithTheScenarioGenomeSeedAndEveryOverride) {
  const std::vector<std::function<void(v1::Job&)>> changes = {
      [](v1::Job& job) { job.set_scenario_json(R"({"duration":2})"); },
      [](v1::Job& job) { job.set_genome_json("[1,3]"); },
      [](v1::Job& job) { job.set_seed(4); },
      [](v1::Job& job) { job.mutable_overrides(0)->set_value("0.8"); },
      [](v1::Job& job) { job.mutable_overrides(0)->set_path("/AngularMotor/MaxVelocity"); },
      [](v1::Job& job) { job.clear_overrides(); },
      [](v1::Job& job) { job.add_overrides()->set_path("/x"); },
      // The same bytes split differently between fields.
      [](v1::Job& job) {
        job.set_scenario_json(R"({"duration":1}[)");
        job.set_genome_json("1,2]");
      },
  };
  const std::string original = JobFingerprint(AJob());
  for (std::size_t i = 0; i < changes.size(); ++i) {
    v1::Job job = AJob();
    changes[i](job);
    EXPECT_NE(JobFingerprint(job), original) << "change " << i;
  }
}

}  // namespace
}  // namespace orcs::regress
