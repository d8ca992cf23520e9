// A result as a results.jsonl line: field names, statuses, null fitness on failure, term means.
#include "proto/result_json.h"

#include <gtest/gtest.h>

namespace orcs::proto {
namespace {

v1::Result TwoSetResult() {
  v1::Result result;
  result.set_job_id("job-7");
  result.set_status(v1::Result::OK);
  result.set_fitness(0.25);
  result.set_worker_id("w1");
  result.set_attempts(2);
  result.mutable_timings()->set_run_seconds(1.5);
  for (int k = 0; k < 2; ++k) {
    v1::Result::ParameterSetResult* set = result.add_parameter_sets();
    set->set_index(static_cast<std::uint32_t>(k));
    set->set_status(v1::Result::OK);
    set->set_fitness(k);
    v1::DrawnValue* drawn = set->add_drawn();
    drawn->set_path("/Floor/Friction");
    drawn->set_value(0.5 + k);
    v1::Term* distance = set->add_terms();
    distance->set_name("distance");
    distance->set_value(1.0 + 2.0 * k);
    v1::Term* energy = set->add_terms();
    energy->set_name("energy");
    energy->set_value(10.0);
  }
  return result;
}

TEST(ResultJsonTest, HoldsEveryFieldInAFixedOrder) {
  const nlohmann::ordered_json line = ResultToJson(TwoSetResult());
  std::vector<std::string> keys;
  for (auto it = line.begin(); it != line.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"id", "status", "fitness", "terms", "sets", "worker", "attempts", "timings",
                                            "message"}));
  EXPECT_EQ(line["id"], "job-7");
  EXPECT_EQ(line["status"], "ok");
  EXPECT_EQ(line["fitness"], 0.25);
  EXPECT_EQ(line["worker"], "w1");
  EXPECT_EQ(line["attempts"], 2);
  EXPECT_EQ(line["timings"]["run_seconds"], 1.5);
  EXPECT_EQ(line["sets"][1]["drawn"]["/Floor/Friction"], 1.5);
  EXPECT_EQ(line["sets"][1]["terms"]["distance"], 3.0);
  EXPECT_FALSE(line["sets"][0].contains("message"));
}

TEST(ResultJsonTest, JobTermsAreTheMeanOverTheSets) {
  const nlohmann::ordered_json line = ResultToJson(TwoSetResult());
  EXPECT_EQ(line["terms"]["distance"], 2.0);
  EXPECT_EQ(line["terms"]["energy"], 10.0);
  EXPECT_EQ(line["terms"].begin().key(), "distance");  // the scenario's order, not alphabetical
}

TEST(ResultJsonTest, AFailedJobHasNoFitnessAndSaysWhy) {
  v1::Result result = TwoSetResult();
  result.set_status(v1::Result::UNSTABLE_PHYSICS);
  result.set_message("parameter set 1: velocity exploded");
  result.mutable_parameter_sets(1)->set_status(v1::Result::UNSTABLE_PHYSICS);
  result.mutable_parameter_sets(1)->set_message("velocity exploded");
  const nlohmann::ordered_json line = ResultToJson(result);
  EXPECT_TRUE(line["fitness"].is_null());
  EXPECT_EQ(line["status"], "unstable_physics");
  EXPECT_EQ(line["message"], "parameter set 1: velocity exploded");
  EXPECT_EQ(line["sets"][1]["message"], "velocity exploded");
}

TEST(ResultJsonTest, NamesEveryStatus) {
  EXPECT_EQ(StatusName(v1::Result::OK), "ok");
  EXPECT_EQ(StatusName(v1::Result::INVALID_INPUT), "invalid_input");
  EXPECT_EQ(StatusName(v1::Result::UNSTABLE_PHYSICS), "unstable_physics");
  EXPECT_EQ(StatusName(v1::Result::TIMEOUT), "timeout");
  EXPECT_EQ(StatusName(v1::Result::WORKER_LOST), "worker_lost");
  EXPECT_EQ(StatusName(v1::Result::INTERNAL_ERROR), "internal_error");
  EXPECT_EQ(StatusName(v1::Result::CRASHED), "crashed");
  EXPECT_EQ(StatusName(v1::Result::STATUS_UNSPECIFIED), "internal_error");
}

TEST(ResultJsonTest, ALineReadBackWritesTheSameLine) {
  v1::Result result = TwoSetResult();
  result.set_engine("MuJoCo");
  result.set_fitness(0.1 + 0.2);  // a double whose shortest text must round-trip exactly
  result.mutable_parameter_sets(1)->set_status(v1::Result::TIMEOUT);
  result.mutable_parameter_sets(1)->set_message("ran too long");
  const nlohmann::ordered_json line = ResultToJson(result);
  const v1::Result back = ResultFromJson(nlohmann::json::parse(line.dump()));
  EXPECT_EQ(ResultToJson(back).dump(), line.dump());
  EXPECT_EQ(back.fitness(), 0.1 + 0.2);
  EXPECT_EQ(back.parameter_sets(1).status(), v1::Result::TIMEOUT);
}

TEST(ResultJsonTest, AFailedLineReadsBackWithoutAFitness) {
  v1::Result failed;
  failed.set_job_id("j");
  failed.set_status(v1::Result::CRASHED);
  failed.set_message("SIGSEGV");
  const v1::Result back = ResultFromJson(nlohmann::json::parse(ResultToJson(failed).dump()));
  EXPECT_EQ(back.status(), v1::Result::CRASHED);
  EXPECT_EQ(back.message(), "SIGSEGV");
  EXPECT_EQ(back.fitness(), 0.0);
}

TEST(ResultJsonTest, AMalformedLineNamesTheField) {
  const auto problem = [](const std::string& text) {
    try {
      ResultFromJson(nlohmann::json::parse(text));
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(problem("[1]"), "expected a JSON object");
  EXPECT_EQ(problem(R"({"status": "ok"})"), "id: missing or empty");
  EXPECT_EQ(problem(R"({"id": "j", "status": "fine"})"), "status: unknown status 'fine'");
  EXPECT_EQ(problem(R"({"id": "j", "status": "ok", "fitness": "high"})"), "fitness: expected a number, found \"high\"");
  EXPECT_EQ(problem(R"({"id": "j", "status": "ok", "sets": [{"index": 0, "terms": {"d": "x"}}]})"),
            "sets[0].terms.d: expected a number");
}

}  // namespace
}  // namespace orcs::proto
