// The output folder: results.jsonl lines (exact numbers, extra fields), the partial file, logs.
#include "clients/runtime/results_writer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/core/error.h"
#include "tests/support/temp_dir.h"

namespace orcs::runtime {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

v1::Result MakeResult(const std::string& id, int sets, double fitness) {
  v1::Result result;
  result.set_job_id(id);
  result.set_status(v1::Result::OK);
  result.set_fitness(fitness);
  for (int k = 0; k < sets; ++k) {
    v1::Result::ParameterSetResult* set = result.add_parameter_sets();
    set->set_index(static_cast<std::uint32_t>(k));
    v1::LogFile* log = result.add_logs();
    log->set_name("set-" + std::to_string(k) + ".csv");
    log->set_csv("time,x\n0," + std::to_string(k) + "\n");
  }
  return result;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ResultsWriterTest, WritesLinesToAPartialFileAndRenamesItWhenFinished) {
  TempDir dir;
  ResultsWriter writer(dir.PathOf("out"));
  writer.Write(MakeResult("job-0", 1, 1.0), {{"seed", 5}});
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "results.jsonl.partial"));
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "results.jsonl"));
  writer.Write(MakeResult("job-1", 1, 2.0), {{"seed", 6}});
  writer.Finish();
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "results.jsonl.partial"));
  std::istringstream lines(Slurp(dir.path() / "out" / "results.jsonl"));
  std::string line;
  std::vector<nlohmann::json> parsed;
  while (std::getline(lines, line)) parsed.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(parsed.size(), 2u);
  EXPECT_EQ(parsed[1]["id"], "job-1");
  EXPECT_EQ(parsed[1]["seed"], 6);
}

TEST(ResultsWriterTest, ExtraFieldsFollowTheId) {
  TempDir dir;
  ResultsWriter writer(dir.PathOf("out"));
  writer.Write(MakeResult("job-0", 1, 1.0), {{"seed", 5}, {"genome_index", 2}});
  writer.Finish();
  const std::string text = Slurp(dir.path() / "out" / "results.jsonl");
  EXPECT_EQ(text.rfind(R"({"id":"job-0","seed":5,"genome_index":2,"status":"ok")", 0), 0u) << text;
}

TEST(ResultsWriterTest, NumbersReadBackToTheSameBits) {
  TempDir dir;
  ResultsWriter writer(dir.PathOf("out"));
  const std::vector<double> values = {0.1 + 0.2, 1.0 / 3.0, -2.5e-300, 123456789.123456789, 5e-324};
  for (std::size_t i = 0; i < values.size(); ++i) {
    writer.Write(MakeResult("job-" + std::to_string(i), 1, values[i]), nlohmann::ordered_json::object());
  }
  writer.Finish();
  std::istringstream lines(Slurp(dir.path() / "out" / "results.jsonl"));
  std::string line;
  for (double expected : values) {
    ASSERT_TRUE(std::getline(lines, line));
    const double read = nlohmann::json::parse(line)["fitness"].get<double>();
    EXPECT_TRUE(SameBits(read, expected)) << line;
  }
}

TEST(ResultsWriterTest, WritesOneLogPerJobOrOnePerParameterSet) {
  TempDir dir;
  ResultsWriter writer(dir.PathOf("out"));
  writer.Write(MakeResult("job-0", 1, 1.0), nlohmann::ordered_json::object());
  writer.Write(MakeResult("job-1", 2, 1.0), nlohmann::ordered_json::object());
  writer.Write(MakeResult("../evil/id", 1, 1.0), nlohmann::ordered_json::object());
  const fs::path logs = dir.path() / "out" / "logs";
  EXPECT_EQ(Slurp(logs / "job-0.csv"), "time,x\n0,0\n");
  EXPECT_EQ(Slurp(logs / "job-1.set-0.csv"), "time,x\n0,0\n");
  EXPECT_EQ(Slurp(logs / "job-1.set-1.csv"), "time,x\n0,1\n");
  EXPECT_TRUE(fs::exists(logs / "_.._evil_id.csv"));  // a job id never escapes the logs folder
}

TEST(ResultsWriterTest, RemovesOldLogsButNothingElse) {
  TempDir dir;
  dir.Write("out/logs/old.csv", "x");
  dir.Write("out/logs/notes.txt", "keep");
  ResultsWriter writer(dir.PathOf("out"));
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "logs" / "old.csv"));
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "logs" / "notes.txt"));
}

TEST(ResultsWriterTest, WritesARecordingBeforeTheLineThatNamesItAndRemovesAnEarlierBatchs) {
  TempDir dir;
  dir.Write("out/recordings/job-9.orcsrec", "old");
  dir.Write("out/recordings/notes.txt", "keep");
  ResultsWriter writer(dir.PathOf("out"));
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "recordings" / "job-9.orcsrec"));
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "recordings" / "notes.txt"));
  v1::Result recorded = MakeResult("job-1", 1, 2.0);
  recorded.set_recording(std::string("ORCSREC\x1a\0bytes", 15));
  writer.Write(recorded, nlohmann::ordered_json::object());
  writer.Write(MakeResult("job-2", 1, 3.0), nlohmann::ordered_json::object());
  writer.Finish();
  EXPECT_EQ(Slurp(dir.path() / "out" / "recordings" / "job-1.orcsrec"), recorded.recording());
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "recordings" / "job-2.orcsrec"));
  std::istringstream lines(Slurp(dir.path() / "out" / "results.jsonl"));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(nlohmann::json::parse(line)["recording"], "recordings/job-1.orcsrec");
  std::getline(lines, line);
  EXPECT_FALSE(nlohmann::json::parse(line).contains("recording"));
}

TEST(ResultsWriterTest, AnUnwritableFolderIsAnInputError) {
  TempDir dir;
  dir.Write("file", "x");
  EXPECT_THROW(ResultsWriter writer(dir.PathOf("file/out")), InputError);
}

}  // namespace
}  // namespace orcs::runtime
