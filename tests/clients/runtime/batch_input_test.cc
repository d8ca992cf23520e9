// orcs-batch's input: scenario files, genome files, the jobs made from them and the checks before submission.
#include "clients/runtime/batch_input.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "model/scene/scenario.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::runtime {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::HasSubstr;

// Two hip oscillators: flat genomes of 8 numbers.
constexpr const char* kScenario = R"({
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]},
  "genome": [10, 1, 0, 0, 10, 1, 3, 0]
})";

class BatchInputTest : public ::testing::Test {
 protected:
  ScenarioInput Scenario(const std::string& text = kScenario) {
    return LoadScenario(dir_.Write("scenario.json", text));
  }
  TempDir dir_;
};

TEST_F(BatchInputTest, ReadsGenomesOnePerLineSkippingBlankAndCommentLines) {
  const std::string path = dir_.Write("g.jsonl", "# header\n[1, 2]\n\n  \n{\"neurons\": []}\n[3]\n");
  const std::vector<Genome> genomes = ReadGenomes(path);
  ASSERT_EQ(genomes.size(), 3u);
  EXPECT_EQ(genomes[0].value, nlohmann::json({1, 2}));
  EXPECT_EQ(genomes[0].line, 2);
  EXPECT_TRUE(genomes[1].value.is_object());
  EXPECT_EQ(genomes[1].line, 5);
  EXPECT_EQ(genomes[2].line, 6);
}

TEST_F(BatchInputTest, NamesTheFileAndLineOfABadGenome) {
  const std::string path = dir_.Write("g.jsonl", "[1, 2]\n[1, 2\n");
  EXPECT_THAT(InputErrorOf([&] { ReadGenomes(path); }), HasSubstr("g.jsonl:2"));
  const std::string scalar = dir_.Write("s.jsonl", "[1]\n\"abc\"\n");
  EXPECT_THAT(InputErrorOf([&] { ReadGenomes(scalar); }), HasSubstr("s.jsonl:2: expected a genome"));
  const std::string empty = dir_.Write("e.jsonl", "# nothing\n");
  EXPECT_THAT(InputErrorOf([&] { ReadGenomes(empty); }), HasSubstr("found none"));
}

TEST_F(BatchInputTest, ReadsAGenomeOptionInlineOrFromAFile) {
  EXPECT_EQ(ParseGenomeOption("[1, 2.5]").value, nlohmann::json({1, 2.5}));
  const std::string path = dir_.Write("one.json", "[4, 5]");
  EXPECT_EQ(ParseGenomeOption("@" + path).value, nlohmann::json({4, 5}));
  EXPECT_THAT(InputErrorOf([] { ParseGenomeOption("[1,"); }), HasSubstr("--genome"));
}

TEST_F(BatchInputTest, RunJobsAreEveryGenomeTimesEverySeedWithSortableIds) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}, {nlohmann::json({2}), "a", 2}};
  const std::vector<PlannedJob> jobs = PlanRunJobs(input, genomes, {.seed = 7, .repeats = 6});
  ASSERT_EQ(jobs.size(), 12u);
  EXPECT_EQ(jobs[0].job.job_id(), "job-00");
  EXPECT_EQ(jobs[11].job.job_id(), "job-11");
  EXPECT_EQ(jobs[5].job.seed(), 12u);  // genome 0, repeat 5
  EXPECT_EQ(jobs[6].job.seed(), 7u);   // genome 1 meets the same seeds
  EXPECT_EQ(jobs[6].job.genome_json(), "[2]");
  EXPECT_EQ(jobs[6].genome, 1);
  EXPECT_EQ(jobs[6].extra["genome_index"], 1);
  EXPECT_EQ(jobs[6].extra["seed"], 7);
  // The job carries the resolved scenario, not a file name.
  EXPECT_EQ(nlohmann::json::parse(jobs[0].job.scenario_json())["duration"], 0.1);
}

TEST_F(BatchInputTest, RecordSelectsAllOrIndicesAndRangesAndNamesTheOptionWhenBad) {
  EXPECT_TRUE(ParseJobSelection("all", 3).all);
  const JobSelection some = ParseJobSelection("0,3-5,9", 10);
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < 10; ++i) {
    if (some.Contains(i)) chosen.push_back(i);
  }
  EXPECT_EQ(chosen, (std::vector<std::size_t>{0, 3, 4, 5, 9}));
  EXPECT_EQ(InputErrorOf([] { ParseJobSelection("1-x", 10); }),
            "--record: expected 'all' or job indices such as 0,3-5, found '1-x'");
  for (const char* bad : {"", "ALL", "1,", ",1", "-1", "1-", "1 ,2", "+1", "1-2-3", "99999999999999999999"}) {
    EXPECT_THAT(InputErrorOf([&] { ParseJobSelection(bad, 10); }), HasSubstr("--record: expected")) << bad;
  }
  EXPECT_EQ(InputErrorOf([] { ParseJobSelection("0,3", 3); }),
            "--record: expected job indices 0…2 (the batch has 3 jobs), found '0,3'");
  EXPECT_THAT(InputErrorOf([] { ParseJobSelection("5-2", 10); }), HasSubstr("FIRST ≤ LAST"));
}

TEST_F(BatchInputTest, RecordedJobsAskForParameterSetZeroAndTheScenarioCanAskForAll) {
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}};
  std::vector<PlannedJob> jobs = PlanRunJobs(Scenario(), genomes, {.seed = 1, .repeats = 4});
  for (const PlannedJob& planned : jobs) EXPECT_FALSE(planned.job.record());
  MarkRecorded(jobs, ParseJobSelection("1-2", jobs.size()));
  EXPECT_FALSE(jobs[0].job.record());
  EXPECT_TRUE(jobs[1].job.record());
  EXPECT_EQ(jobs[1].job.record_set(), 0u);
  EXPECT_TRUE(jobs[2].job.record());
  EXPECT_FALSE(jobs[3].job.record());

  nlohmann::json recorded = nlohmann::json::parse(kScenario);
  recorded["record"] = true;
  for (const PlannedJob& planned : PlanRunJobs(Scenario(recorded.dump()), genomes, {.seed = 1, .repeats = 2})) {
    EXPECT_TRUE(planned.job.record());
  }
}

// No job leaves without a time limit: the broker's lease and the worker's watch over its simulation process both
// follow it (docs/protocol.md, "Leases").
TEST_F(BatchInputTest, EveryJobHasATimeLimitTheUsersOrOneFromItsSimulatedDuration) {
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}};
  nlohmann::json scenario = nlohmann::json::parse(kScenario);
  scenario["duration"] = 2.5;
  scenario["randomisation"] = {{"sets", 4}};
  const ScenarioInput input = Scenario(scenario.dump());
  for (const PlannedJob& planned : PlanRunJobs(input, genomes, {.seed = 1, .repeats = 2})) {
    EXPECT_EQ(planned.job.time_limit_seconds(), 30.0 + 10.0 * 2.5 * 4);
  }
  for (const PlannedJob& planned :
       PlanRunJobs(input, genomes, {.seed = 1, .repeats = 1, .time_limit_seconds = 7.5})) {
    EXPECT_EQ(planned.job.time_limit_seconds(), 7.5);
  }
}

TEST_F(BatchInputTest, SweepJobsCarryThePointAsOverridesThatReadBackExactly) {
  const ScenarioInput input = Scenario();
  const std::vector<SweepPoint> points = {{{"/AngularMotor/PID/Proportional", 0.1 + 0.2}}, {{"/AngularMotor/PID/Proportional", 30}}};
  const std::vector<PlannedJob> jobs = PlanSweepJobs(input, DefaultGenome(input), points, {.seed = 3, .repeats = 2});
  ASSERT_EQ(jobs.size(), 4u);
  EXPECT_EQ(jobs[0].job.job_id(), "point-0-r0");
  EXPECT_EQ(jobs[3].job.job_id(), "point-1-r1");
  EXPECT_EQ(jobs[1].job.seed(), 4u);
  ASSERT_EQ(jobs[0].job.overrides_size(), 1);
  EXPECT_EQ(std::stod(jobs[0].job.overrides(0).value()), 0.1 + 0.2);
  EXPECT_EQ(jobs[2].extra["params"]["/AngularMotor/PID/Proportional"], 30.0);
  EXPECT_EQ(jobs[2].extra["point"], 1);
}

TEST_F(BatchInputTest, ACategoryTravelsAsItsNameAndPassesTheChecks) {
  const ScenarioInput input = Scenario();
  const std::vector<SweepPoint> points = {{{"/Sim/Floor/Material", SweepValue("Carpet", 1)}}};
  const std::vector<PlannedJob> jobs = PlanSweepJobs(input, DefaultGenome(input), points, {});
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(jobs[0].job.overrides(0).value(), "Carpet");
  EXPECT_EQ(jobs[0].extra["params"]["/Sim/Floor/Material"], "Carpet");
  EXPECT_NO_THROW(CheckJobs(input, {DefaultGenome(input)}, jobs));
  // A value the repository cannot read for its path is caught before submission, as for numbers.
  const std::vector<SweepPoint> bad = {{{"/AngularMotor/PID/Proportional", SweepValue("fast", 0)}}};
  const std::vector<PlannedJob> bad_jobs = PlanSweepJobs(input, DefaultGenome(input), bad, {});
  EXPECT_THAT(InputErrorOf([&] { CheckJobs(input, {DefaultGenome(input)}, bad_jobs); }),
              HasSubstr("/AngularMotor/PID/Proportional"));
}

// The documented robustness example (docs/batch.md) sweeps the gain, the floor friction and the floor's material.
TEST_F(BatchInputTest, TheRobustnessExampleAcceptsItsSweep) {
  const ScenarioInput input = LoadScenario(ORCS_SOURCE_DIR "/scenarios/examples/swing_robustness.json");
  const std::vector<SweepPoint> points = {{{"/AngularMotor/PID/Proportional", 10.0},
                                           {"/Simulation/ODE/FrictionScaling", 1.5},
                                           {"/Sim/Floor/Material", SweepValue("Carpet", 2)}}};
  const std::vector<Genome> genomes = {DefaultGenome(input)};
  EXPECT_NO_THROW(CheckJobs(input, genomes, PlanSweepJobs(input, genomes[0], points, {})));
}

TEST_F(BatchInputTest, ASweptPathTheRandomisationDrawsAbsolutelyIsRejected) {
  const ScenarioInput input = Scenario(R"({
    "controller": {"type": "oscillator", "joints": []}, "fitness": {"terms": [{"type": "energy"}]},
    "randomisation": {"sets": 2, "parameters": [
      {"path": "/AngularMotor/PID/Proportional", "uniform": [10, 20]},
      {"path": "/AngularMotor/MaxVelocity", "uniform": [0.9, 1.1], "relative": true}]}})");
  const Genome genome = DefaultGenome(input);
  EXPECT_THAT(InputErrorOf([&] { PlanSweepJobs(input, genome, {{{"/AngularMotor/PID/Proportional", 5}}}, {}); }),
              HasSubstr("--param /AngularMotor/PID/Proportional: the scenario's randomisation.parameters[0] draws"));
  EXPECT_EQ(PlanSweepJobs(input, genome, {{{"/AngularMotor/MaxVelocity", 5}}}, {}).size(), 1u);  // relative: fine
}

TEST_F(BatchInputTest, DefaultGenomeIsTheScenariosOrEmpty) {
  EXPECT_EQ(DefaultGenome(Scenario()).value.size(), 8u);
  const ScenarioInput none = Scenario(R"({"controller": {"type": "oscillator", "joints": []},
                                          "fitness": {"terms": [{"type": "energy"}]}})");
  EXPECT_EQ(DefaultGenome(none).value, nlohmann::json::array());
}

TEST_F(BatchInputTest, ChecksPassForGoodJobs) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {DefaultGenome(input)};
  EXPECT_NO_THROW(CheckJobs(input, genomes, PlanRunJobs(input, genomes, {})));
}

TEST_F(BatchInputTest, AGenomeOfTheWrongLengthIsNamedByFileAndLine) {
  const ScenarioInput input = Scenario();
  const std::string path = dir_.Write("g.jsonl", "[1,2,3,4,5,6,7,8]\n[1,2,3]\n");
  const std::vector<Genome> genomes = ReadGenomes(path);
  EXPECT_THAT(InputErrorOf([&] { CheckJobs(input, genomes, PlanRunJobs(input, genomes, {})); }),
              HasSubstr("g.jsonl:2: field 'genome' expected 8 numbers, found an array of 3"));
}

TEST_F(BatchInputTest, AnUnknownSweptPathIsCaughtBeforeSubmission) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {DefaultGenome(input)};
  const std::vector<SweepPoint> points = {{{"/No/Such/Value", 1.0}}};
  EXPECT_THAT(InputErrorOf([&] { CheckJobs(input, genomes, PlanSweepJobs(input, genomes[0], points, {})); }),
              HasSubstr("/No/Such/Value"));
}

TEST_F(BatchInputTest, AnUnknownPathInADistributionIsCaughtWithTheScenarioField) {
  const ScenarioInput input = Scenario(R"({
    "controller": {"type": "oscillator", "joints": []}, "fitness": {"terms": [{"type": "energy"}]},
    "randomisation": {"sets": 2, "parameters": [{"path": "/No/Such/Value", "uniform": [0, 1]}]}})");
  const std::vector<Genome> genomes = {DefaultGenome(input)};
  const std::string message = InputErrorOf([&] { CheckJobs(input, genomes, PlanRunJobs(input, genomes, {})); });
  EXPECT_THAT(message, HasSubstr("scenario.json"));
  EXPECT_THAT(message, HasSubstr("/No/Such/Value"));
}

TEST_F(BatchInputTest, ScenarioErrorsNameTheFileAndField) {
  EXPECT_THAT(InputErrorOf([&] { Scenario(R"({"controller": {}, "fitness": {}, "durration": 1})"); }),
              HasSubstr("durration"));
  EXPECT_THAT(InputErrorOf([&] { Scenario(R"({"controller": {}, "fitness": {}, "genome": 5})"); }),
              HasSubstr("field 'genome'"));
  EXPECT_THAT(InputErrorOf([&] { LoadScenario(dir_.PathOf("missing.json")); }), HasSubstr("missing.json"));
}

// ---------------------------------------------------------------------------------------------------------------
// Job sources (docs/batch.md, "Large batches"): a job is made from its index, when the session's window has room.

// Counts the jobs a source is asked to make, so that a test can tell a check that makes every job from one that
// does not.
class CountingSource : public JobSource {
 public:
  explicit CountingSource(const JobSource& inner) : inner_(inner) {}
  std::size_t size() const override { return inner_.size(); }
  std::vector<std::size_t> Representatives() const override { return inner_.Representatives(); }
  int made() const { return made_; }

 protected:
  PlannedJob Make(std::size_t index) const override {
    ++made_;
    return inner_.Job(index);
  }

 private:
  const JobSource& inner_;
  mutable int made_ = 0;
};

TEST_F(BatchInputTest, ARunSourceMakesAnyJobOfAMillionFromItsIndexAlone) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}, {nlohmann::json({2}), "a", 2}};
  const RunJobSource source(input, genomes, {.seed = 7, .repeats = 500000});
  ASSERT_EQ(source.size(), 1000000u);
  const PlannedJob last = source.Job(999999);  // genome 1, repeat 499999
  EXPECT_EQ(last.job.job_id(), "job-999999");
  EXPECT_EQ(last.job.seed(), 7u + 499999u);
  EXPECT_EQ(last.job.genome_json(), "[2]");
  EXPECT_EQ(last.genome, 1);
  EXPECT_EQ(last.extra["genome_index"], 1);
  EXPECT_EQ(last.extra["seed"], 7 + 499999);
  const PlannedJob middle = source.Job(500000);  // genome 1 meets the seeds genome 0 met
  EXPECT_EQ(middle.job.job_id(), "job-500000");
  EXPECT_EQ(middle.job.seed(), 7u);
  EXPECT_EQ(source.Job(0).job.job_id(), "job-000000");
  EXPECT_EQ(source.Job(0).job.scenario_json(), input.resolved_json);
}

TEST_F(BatchInputTest, ASourcesJobsAreThePlannedJobsInOrderAndTheSameEveryTime) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}, {nlohmann::json({2}), "a", 2},
                                       {nlohmann::json({3}), "a", 3}};
  const RunJobSource source(input, genomes, {.seed = 11, .repeats = 4});
  ASSERT_EQ(source.size(), 12u);
  std::set<std::string> ids;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const PlannedJob planned = source.Job(i);
    const PlannedJob again = source.Job(i);
    EXPECT_EQ(planned.job.SerializeAsString(), again.job.SerializeAsString()) << i;
    EXPECT_EQ(planned.extra, again.extra) << i;
    // Genome-major, as docs/batch.md promises: job g·N + r is genome g, repeat r.
    EXPECT_EQ(planned.job.genome_json(), genomes[i / 4].value.dump()) << i;
    EXPECT_EQ(planned.job.seed(), 11u + i % 4) << i;
    ids.insert(planned.job.job_id());
  }
  EXPECT_EQ(ids.size(), 12u);
  EXPECT_EQ(*ids.begin(), "job-00");
  EXPECT_EQ(*ids.rbegin(), "job-11");
}

TEST_F(BatchInputTest, ASweepSourceMakesPointMajorJobsAndChecksOneJobPerPoint) {
  const ScenarioInput input = Scenario();
  std::vector<SweepPoint> points;
  for (int p = 0; p < 5; ++p) points.push_back({{"/AngularMotor/PID/Proportional", 10.0 + p}});
  const SweepJobSource source(input, DefaultGenome(input), points, {.seed = 3, .repeats = 3});
  ASSERT_EQ(source.size(), 15u);
  EXPECT_EQ(source.Representatives(), (std::vector<std::size_t>{0, 3, 6, 9, 12}));
  const PlannedJob job = source.Job(13);  // point 4, repeat 1
  EXPECT_EQ(job.job.job_id(), "point-4-r1");
  EXPECT_EQ(job.job.seed(), 4u);
  ASSERT_EQ(job.job.overrides_size(), 1);
  EXPECT_EQ(job.job.overrides(0).value(), "14");
  EXPECT_EQ(job.extra["point"], 4);
  EXPECT_EQ(job.extra["params"]["/AngularMotor/PID/Proportional"], 14.0);
}

TEST_F(BatchInputTest, ASourceRecordsTheSelectedIndices) {
  const std::vector<Genome> genomes = {{nlohmann::json({1}), "a", 1}};
  const ScenarioInput input = Scenario();
  RunJobSource source(input, genomes, {.seed = 1, .repeats = 1000});
  source.Record(ParseJobSelection("1-2,999", source.size()));
  for (std::size_t i : {std::size_t{0}, std::size_t{3}, std::size_t{998}}) {
    EXPECT_FALSE(source.Job(i).job.record()) << i;
  }
  for (std::size_t i : {std::size_t{1}, std::size_t{2}, std::size_t{999}}) {
    EXPECT_TRUE(source.Job(i).job.record()) << i;
    EXPECT_EQ(source.Job(i).job.record_set(), 0u) << i;
  }
}

// The checks before submission cover a million-job batch without making a million jobs, and still find what
// would fail only late in the batch: a bad genome on the last line, a bad value at the last sweep point.
TEST_F(BatchInputTest, CheckingASourceMakesOnlyItsRepresentativesAndFindsALateBadJob) {
  const ScenarioInput input = Scenario();
  const std::vector<Genome> genomes = {DefaultGenome(input)};
  const RunJobSource run(input, genomes, {.seed = 1, .repeats = 1000000});
  const CountingSource counting(run);
  EXPECT_NO_THROW(CheckJobs(input, genomes, counting));
  EXPECT_LE(counting.made(), 2);

  const std::string path = dir_.Write("g.jsonl", "[1,2,3,4,5,6,7,8]\n[1,2,3,4,5,6,7,8]\n[1,2,3]\n");
  const std::vector<Genome> late = ReadGenomes(path);
  const RunJobSource late_run(input, late, {.seed = 1, .repeats = 100000});
  EXPECT_THAT(InputErrorOf([&] { CheckJobs(input, late, late_run); }),
              HasSubstr("g.jsonl:3: field 'genome' expected 8 numbers"));

  std::vector<SweepPoint> points;
  for (int p = 0; p < 20; ++p) points.push_back({{"/AngularMotor/PID/Proportional", SweepValue(10.0 + p)}});
  points.back() = {{"/AngularMotor/PID/Proportional", SweepValue("fast", 0)}};
  const SweepJobSource sweep(input, genomes[0], points, {.seed = 1, .repeats = 1000});
  const CountingSource counting_sweep(sweep);
  EXPECT_THAT(InputErrorOf([&] { CheckJobs(input, genomes, counting_sweep); }),
              HasSubstr("/AngularMotor/PID/Proportional"));
  EXPECT_LE(counting_sweep.made(), 21);  // one per point (and job 0), not 20,000
}

}  // namespace
}  // namespace orcs::runtime
