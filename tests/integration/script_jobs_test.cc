// Scripts in jobs through the real programs (issue 50): `orcs-batch run` with its embedded broker and one local
// orcs-worker on 127.0.0.1 runs hostile script controllers one after another — os.execute, io.open, require, loading
// bytecode, an endless loop, a 10 GB table, deep recursion, a huge error message. Each fails its own job with a named
// status and one line naming the script's line; the same worker then runs an honest job to the end.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>

#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";

// genome[1] picks what the controller tries in its first control step; 0 tries nothing.
constexpr const char* kHostileScript = R"(local tries = {
  [1] = function() os.execute("touch /tmp/orcs-script-was-here") end,
  [2] = function() io.open("/etc/passwd") end,
  [3] = function() require("socket") end,
  [4] = function() load(string.dump(function() return 1 end))() end,
  [5] = function() while true do end end,
  [6] = function() local t = {} for i = 1, 1e10 do t[i] = i end end,
  [7] = function() local function f(n) return 1 + f(n + 1) end return f(1) end,
  [8] = function() error(string.rep("spam ", 1e6)) end,
}
function control(t)
  local try = tries[genome[1]]
  if try then try() end
  orcs.set_angle("Right/Knee", 10)
end
)";

constexpr const char* kScenario = R"({"name": "hostile", "duration": 0.2,
 "controller": {"type": "script", "script": "hostile.lua", "genome_length": 1},
 "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]}})";

struct Expected {
  int genome;
  const char* status;
  const char* says;  // in the message, after "parameter set 0: script "
};

TEST(ScriptJobsTest, HostileScriptsFailTheirOwnJobsAndTheWorkerServesTheNext) {
  TempDir dir;
  dir.Write("hostile.lua", kHostileScript);
  const std::string scenario = dir.Write("hostile.json", kScenario);
  const std::vector<Expected> expected = {
      {1, "script_error", "hostile.lua:2: os.execute is not available"},
      {2, "script_error", "hostile.lua:3: io.open is not available"},
      {3, "script_error", "hostile.lua:4: require is not available"},
      {4, "script_error", "hostile.lua:5: string.dump is not available"},
      {5, "script_limit", "'hostile.lua' line 6: instruction budget of 200000000"},
      {6, "script_limit", "'hostile.lua' line 7: memory cap of 64 MiB"},
      {7, "script_error", "hostile.lua:8: stack overflow"},
      {8, "script_error", "hostile.lua:9: spam spam"},
      {0, "ok", ""}};
  std::ostringstream genomes;
  for (const Expected& job : expected) genomes << "[" << job.genome << "]\n";
  const std::string out = dir.PathOf("out");
  const ProcessResult run = RunProcess({kBin + "orcs-batch", "run", scenario, "--genomes",
                                        dir.Write("genomes.jsonl", genomes.str()), "--workers", "1", "--out", out});
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;  // some jobs failed
  EXPECT_THAT(run.out + run.err, HasSubstr("9 of 9 jobs ran: 1 ok, 8 failed (script_error 6, script_limit 2)"));
  EXPECT_FALSE(std::filesystem::exists("/tmp/orcs-script-was-here"));

  std::istringstream lines(dir.Read(out + "/results.jsonl"));
  std::map<std::string, nlohmann::json> results;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json result = nlohmann::json::parse(line);
    results[result["id"]] = result;
  }
  ASSERT_EQ(results.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const nlohmann::json& result = results.at("job-" + std::to_string(i));
    SCOPED_TRACE(result.dump().substr(0, 400));
    EXPECT_EQ(result["status"], expected[i].status);
    if (std::string(expected[i].status) == "ok") {
      EXPECT_EQ(result["sets"].size(), 1u);  // the worker ran the honest job after all the others
      continue;
    }
    const std::string message = result["message"];
    EXPECT_THAT(message, HasSubstr(std::string("parameter set 0: script ") + expected[i].says));
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_LT(message.size(), 600u);
  }
  // One worker did every job: the failures did not cost it.
  std::set<std::string> workers;
  for (const auto& [id, result] : results) workers.insert(result["worker"].get<std::string>());
  EXPECT_EQ(workers.size(), 1u);
}

// The shipped CPG example (a script controller with foot-contact feedback), shortened, evolves through orcs-batch
// evolve's embedded broker on two local workers; the winner replays with orcs-sim to the champion's bits.
TEST(ScriptJobsTest, TheCpgExampleEvolvesAndItsWinnerReplaysToTheSameBits) {
  TempDir dir;
  const std::string examples = ORCS_SOURCE_DIR "/scenarios/examples/";
  nlohmann::json scenario = nlohmann::json::parse(dir.Read(examples + "cpg_walk.json"));
  scenario["controller"]["script"] = examples + "scripts/cpg_feedback.lua";
  scenario["duration"] = 0.5;
  scenario["randomisation"]["sets"] = 2;
  scenario["evolution"]["population"] = 5;
  scenario["evolution"]["generations"] = 2;
  scenario["evolution"]["validate"] = 2;
  const std::string path = dir.Write("cpg.json", scenario.dump(1));
  const std::string out = dir.PathOf("evolve");
  const ProcessResult run =
      RunProcess({kBin + "orcs-batch", "evolve", path, "--workers", "2", "--no-plot", "--out", out});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_THAT(run.out, HasSubstr("(the same bits)"));
  EXPECT_THAT(run.err, HasSubstr("generation 2/2"));
  const nlohmann::json champion = nlohmann::json::parse(dir.Read(out + "/checkpoint.json"))["champion"];
  ASSERT_EQ(champion["genome"].size(), 6u);
  EXPECT_NE(champion["genome"], scenario["genome"]);  // the search moved
  const ProcessResult sim =
      RunProcess({kBin + "orcs-sim", "--scenario", path, "--genome", "@" + out + "/best_genome.json", "--seed", "1"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(nlohmann::json::parse(sim.out)["fitness"].get<double>(), champion["fitness"].get<double>());
}

// A script that does not compile stops orcs-batch before anything is submitted, naming the script and line.
TEST(ScriptJobsTest, ASyntaxErrorStopsTheBatchBeforeItRuns) {
  TempDir dir;
  dir.Write("hostile.lua", "function control(t)\n  orcs.set_angle('Right/Knee', \nend\n");
  const std::string scenario = dir.Write("hostile.json", kScenario);
  const ProcessResult run = RunProcess({kBin + "orcs-batch", "run", scenario, "--genome", "[0]", "--workers", "1",
                                        "--out", dir.PathOf("out"), "--quiet"});
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_THAT(run.err, AllOf(HasSubstr("script hostile.lua:3:"), HasSubstr("unexpected symbol")));
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
}

}  // namespace
}  // namespace orcs
