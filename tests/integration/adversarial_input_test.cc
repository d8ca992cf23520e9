// Hostile and careless input (issue 18, items 1, 5 (inputs), 6 and 7), each case against the real programs on
// 127.0.0.1 and each bounded in time: a pattern that is exponential for a backtracking engine, JSON nested
// 100,000 deep, /dev/zero, a FIFO and a directory where a file is expected, an oversized file, 64+ throwaway OSP
// INITs, and numbers that make no sense (time steps, seeds, time limits, joint angles, endpoints). Every case must
// end in one clear line naming the file or field and exit 2 (command line), INVALID_INPUT (a job) or an OSP
// refusal — never a hang, a crash or a silent "ok". docs/reliability.md, "Hostile and careless input (issue 18)".
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "clients/runtime/batch_client.h"
#include "tests/support/background_process.h"
#include "tests/support/batch_collector.h"
#include "tests/support/broker_process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/udp_peer.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
const std::string kSource = ORCS_SOURCE_DIR;
const std::string kEnvironment = kSource + "/scenarios/environments/example.xml";
// The pattern that keeps a backtracking engine busy for minutes on a repository path of ~40 characters.
const std::string kEvilPattern = "(.*)*(.*)*(.*)*(.*)*(.*)*X";

// Hip oscillators for a tenth of a second, one parameter set.
constexpr const char* kScenario = R"({
  "name": "hips",
  "duration": 0.1,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]},
  "genome": [20, 2, 0, 0, 20, 2, 3, 0]
})";

// Runs a program to its end, but for at most `limit`: a hang is a failure (the process is killed), not a test
// that never ends.
ProcessResult RunBounded(const std::vector<std::string>& argv, milliseconds limit = milliseconds(30000)) {
  BackgroundProcess process(argv);
  std::optional<ProcessResult> result = process.Wait(limit);
  if (!result) {
    ADD_FAILURE() << argv[0] << " still ran after " << limit.count() << " ms (a hang); stderr: " << process.err();
    process.Signal(SIGKILL);
    result = process.Wait(milliseconds(5000));
  }
  return result.value_or(ProcessResult{});
}

// Bad input: exit 2, no signal, one line on stderr.
void ExpectOneLineBadInput(const ProcessResult& result) {
  EXPECT_EQ(result.signal, 0) << result.err;
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

std::string Nested(int depth) { return std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']'); }

class AdversarialInputTest : public ::testing::Test {
 protected:
  std::string Scenario(const nlohmann::json& changes = nlohmann::json::object()) {
    nlohmann::json scenario = nlohmann::json::parse(kScenario);
    scenario.merge_patch(changes);
    return dir_.Write("scenario" + std::to_string(++files_) + ".json", scenario.dump());
  }
  std::string Out() { return dir_.PathOf("out" + std::to_string(++files_)); }
  // A FIFO nobody writes to: reading it would block for ever.
  std::string Fifo() {
    const std::string path = dir_.PathOf("fifo" + std::to_string(++files_));
    EXPECT_EQ(mkfifo(path.c_str(), 0600), 0);
    return path;
  }
  TempDir dir_;
  int files_ = 0;
};

// ---------------------------------------------------------------------------------------------------------
// Item 5 (inputs): JSON depth, non-regular files, size bounds.

TEST_F(AdversarialInputTest, JsonNested100000DeepIsOneLineNotASegfault) {
  const std::string deep = dir_.Write("deep.json", Nested(100000));
  // The genome file (orcs-batch crashed with SIGSEGV here), the scenario itself, and the genome as text.
  const ProcessResult genome = RunBounded({kBin + "orcs-batch", "run", Scenario(), "--genome", "@" + deep, "--workers",
                                           "1", "--quiet", "--out", Out()});
  ExpectOneLineBadInput(genome);
  EXPECT_THAT(genome.err, HasSubstr(deep + ":1: JSON nested deeper than 256 levels"));

  const std::string deep_scenario =
      dir_.Write("deep_scenario.json", std::string(kScenario).substr(0, std::string(kScenario).rfind('}')) +
                                           ", \"comment\": " + Nested(100000) + "}");
  for (const std::string& program : {std::string("orcs-batch"), std::string("orcs-sim")}) {
    SCOPED_TRACE(program);
    const ProcessResult scenario =
        program == "orcs-batch"
            ? RunBounded({kBin + program, "run", deep_scenario, "--workers", "1", "--quiet", "--out", Out()})
            : RunBounded({kBin + program, "--scenario", deep_scenario});
    ExpectOneLineBadInput(scenario);
    EXPECT_THAT(scenario.err, HasSubstr(deep_scenario + ":7: JSON nested deeper than 256 levels"));  // its last line
  }

  // 256 levels are still accepted by the reader: the bound is where it is documented.
  const ProcessResult at_bound = RunBounded(
      {kBin + "orcs-batch", "run", Scenario(), "--genome", Nested(256), "--workers", "1", "--quiet", "--out", Out()});
  EXPECT_EQ(at_bound.exit_code, 2);
  EXPECT_THAT(at_bound.err, Not(HasSubstr("nested deeper")));  // refused as a genome, not for its depth
}

TEST_F(AdversarialInputTest, DevZeroAFifoAndADirectoryAreRefusedNamingTheFileAndNothingHangs) {
  const std::string scenario = Scenario();
  for (const std::string& bad : {std::string("/dev/zero"), Fifo(), dir_.path().string()}) {
    SCOPED_TRACE(bad);
    const std::vector<std::vector<std::string>> runs = {
        {kBin + "orcs-batch", "run", bad, "--workers", "1", "--quiet", "--out", Out()},                   // scenario
        {kBin + "orcs-batch", "run", scenario, "--genome", "@" + bad, "--workers", "1", "--quiet", "--out", Out()},
        {kBin + "orcs-batch", "run", scenario, "--genomes", bad, "--workers", "1", "--quiet", "--out", Out()},
        {kBin + "orcs-sim", "--scenario", bad},
        {kBin + "orcs-sim", "-env", bad, "--duration", "0.01"},                                            // environment
        {kBin + "orcs-sim", "-env", kEnvironment, "-val", bad, "--duration", "0.01"},                     // value file
        {kBin + "orcs-sim", "-play", "Humanoid", bad, "--duration", "0.01"},                               // motion record
        {kBin + "orcs-gap", "--rig", "pendulum", "--measured", bad, "--out", Out()},                       // measured run
        {kBin + "orcs-osp", "-env", bad, "-port", "0", "-odcp_port", "0"},
    };
    for (const std::vector<std::string>& argv : runs) {
      SCOPED_TRACE(argv[0] + " " + argv[1] + " " + argv[2]);
      const Clock::time_point start = Clock::now();
      const ProcessResult result = RunBounded(argv);
      ExpectOneLineBadInput(result);
      EXPECT_THAT(result.err, HasSubstr(bad + ": not a regular file"));
      EXPECT_THAT(result.err, Not(HasSubstr("bad_alloc")));
      EXPECT_LT(Clock::now() - start, std::chrono::seconds(15));
    }
  }
}

TEST_F(AdversarialInputTest, AFileBeyondItsSizeBoundIsRefusedBeforeItIsRead) {
  // A sparse file of 64 MiB + 1 byte: nothing is written, the bound alone refuses it.
  const std::string big = dir_.PathOf("big.json");
  {
    const int fd = open(big.c_str(), O_CREAT | O_WRONLY, 0600);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, (std::int64_t{64} << 20) + 1), 0);
    close(fd);
  }
  const ProcessResult scenario = RunBounded({kBin + "orcs-batch", "run", big, "--workers", "1", "--quiet", "--out", Out()});
  ExpectOneLineBadInput(scenario);
  EXPECT_THAT(scenario.err, HasSubstr(big + ": larger than the 64 MiB limit for an input file"));
  const ProcessResult environment = RunBounded({kBin + "orcs-sim", "-env", big, "--duration", "0.01"});
  ExpectOneLineBadInput(environment);
  EXPECT_THAT(environment.err, HasSubstr(big + ": larger than the 64 MiB limit"));
}

// ---------------------------------------------------------------------------------------------------------
// Item 1: user regular expressions run on RE2, bounded in length.

TEST_F(AdversarialInputTest, AnExponentialPatternReturnsPromptlyInOrcsSimAndOrcsBatch) {
  const Clock::time_point start = Clock::now();
  const ProcessResult printed = RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "--print-values", kEvilPattern},
                                           milliseconds(20000));
  EXPECT_EQ(printed.exit_code, 0) << printed.err;
  EXPECT_EQ(printed.out, "");  // no path ends in X
  const ProcessResult logged = RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "--duration", "0.05", "--log",
                                           kEvilPattern + "|/Simulation/CurrentStep", "--out", dir_.PathOf("log.csv")},
                                          milliseconds(20000));
  EXPECT_EQ(logged.exit_code, 0) << logged.err;
  EXPECT_THAT(dir_.Read("log.csv"), HasSubstr("/Simulation/CurrentStep"));
  const std::string out = Out();
  const ProcessResult batch =
      RunBounded({kBin + "orcs-batch", "run", Scenario({{"log", {kEvilPattern + "|/Simulation/CurrentStep"}}}),
                  "--workers", "1", "--quiet", "--out", out},
                 milliseconds(60000));
  EXPECT_EQ(batch.exit_code, 0) << batch.err;
  EXPECT_TRUE(fs::exists(out + "/results.jsonl"));
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(60));
}

// An environment nested 100,000 elements deep (one per line): tinyxml2's own bound stops its recursive parser
// before the stack overflows, and the reader turns that into the documented one-line error naming file and line.
TEST_F(AdversarialInputTest, AnEnvironmentNested100000DeepIsOneLineNotACrash) {
  std::string xml = "<ORCS version=\"1.0\">\n<Environment>\n";
  for (int i = 0; i < 100000; ++i) xml += "<object>\n";
  for (int i = 0; i < 100000; ++i) xml += "</object>";
  const std::string deep = dir_.Write("deep.xml", xml + "\n</Environment>\n</ORCS>\n");
  for (const std::vector<std::string>& argv : std::vector<std::vector<std::string>>{
           {kBin + "orcs-sim", "-env", deep, "--duration", "0.01"},
           {kBin + "orcs-osp", "-env", deep, "-port", "0", "-odcp_port", "0"}}) {
    SCOPED_TRACE(argv[0]);
    const Clock::time_point start = Clock::now();
    const ProcessResult result = RunBounded(argv);
    ExpectOneLineBadInput(result);
    EXPECT_THAT(result.err, ::testing::ContainsRegex(deep + ":[0-9]+: XML elements nested deeper than 32 levels"));
    EXPECT_LT(Clock::now() - start, std::chrono::seconds(15));
  }
}

TEST_F(AdversarialInputTest, AnOverLongPatternIsRefusedWithOneLine) {
  const std::string long_pattern(1001, 'a');
  const ProcessResult printed = RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "--print-values", long_pattern});
  ExpectOneLineBadInput(printed);
  EXPECT_THAT(printed.err, HasSubstr("regular expression of 1001 characters: at most 1000 are accepted"));
  const ProcessResult batch = RunBounded(
      {kBin + "orcs-batch", "run", Scenario({{"log", {long_pattern}}}), "--workers", "1", "--quiet", "--out", Out()});
  ExpectOneLineBadInput(batch);
  EXPECT_THAT(batch.err, HasSubstr("at most 1000 are accepted"));
}

// ---------------------------------------------------------------------------------------------------------
// Item 7: nonsense that used to pass.

TEST_F(AdversarialInputTest, ATimeStepOutsideItsRangeIsRefusedNamingThePath) {
  for (const char* step : {"1e-300", "1e300", "-1", "inf"}) {
    SCOPED_TRACE(step);
    const std::string val = dir_.Write("step.val", std::string("/Simulation/TimeStepSize=") + step + "\n");
    const ProcessResult sim = RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "-val", val, "--duration", "0.1"});
    ExpectOneLineBadInput(sim);
    EXPECT_THAT(sim.err, AllOf(HasSubstr(val + ":1: "), HasSubstr("/Simulation/TimeStepSize"),
                               HasSubstr("a number from 1e-05 to 0.1")));
    // In a scenario: refused before a job runs (it gave status "ok", fitness 0 and 0 steps).
    const ProcessResult batch = RunBounded({kBin + "orcs-batch", "run",
                                            Scenario({{"values", {{"/Simulation/TimeStepSize", step}}}}),
                                            "--workers", "1", "--quiet", "--out", Out()});
    ExpectOneLineBadInput(batch);
    EXPECT_THAT(batch.err, AllOf(HasSubstr("/Simulation/TimeStepSize"), HasSubstr("a number from 1e-05 to 0.1")));
  }
  const std::string fine = dir_.Write("fine.val", "/Simulation/TimeStepSize=0.005\n");
  EXPECT_EQ(RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "-val", fine, "--duration", "0.02"}).exit_code, 0);
}

TEST_F(AdversarialInputTest, SeedsTimeLimitsAndEndpointsThatAreNotNumbersOrAddressesAreExit2) {
  const std::string scenario = Scenario();
  for (const char* seed : {"-1", "1e23", "18446744073709551616", "12abc", ""}) {
    SCOPED_TRACE(seed);
    const ProcessResult batch =
        RunBounded({kBin + "orcs-batch", "run", scenario, "--seed", seed, "--workers", "1", "--quiet", "--out", Out()});
    ExpectOneLineBadInput(batch);
    EXPECT_THAT(batch.err, AllOf(HasSubstr("--seed"), HasSubstr("expected a seed")));
    const ProcessResult sim = RunBounded({kBin + "orcs-sim", "-env", kEnvironment, "--seed", seed, "--duration", "0.01"});
    ExpectOneLineBadInput(sim);
    EXPECT_THAT(sim.err, HasSubstr("expected a seed, an integer from 0 to 18446744073709551615"));
  }
  const ProcessResult max_seed = RunBounded(
      {kBin + "orcs-sim", "-env", kEnvironment, "--seed", "18446744073709551615", "--duration", "0.01"});
  EXPECT_EQ(max_seed.exit_code, 0) << max_seed.err;

  for (const char* limit : {"nan", "-1", "inf", "1e300"}) {
    SCOPED_TRACE(limit);
    const ProcessResult batch = RunBounded(
        {kBin + "orcs-batch", "run", scenario, "--time-limit", limit, "--workers", "1", "--quiet", "--out", Out()});
    ExpectOneLineBadInput(batch);
    EXPECT_THAT(batch.err, AllOf(HasSubstr("--time-limit"), HasSubstr(std::string("found '") + limit + "'")));
  }

  for (const char* endpoint : {"nonsense", "tcp://127.0.0.1", "tcp://127.0.0.1:0", "tcp://127.0.0.1:99999", "http://x:1"}) {
    SCOPED_TRACE(endpoint);
    const ProcessResult submit =
        RunBounded({kBin + "orcs-batch", "submit", scenario, "--broker", endpoint, "--quiet", "--out", Out()});
    ExpectOneLineBadInput(submit);
    EXPECT_THAT(submit.err, AllOf(HasSubstr("--broker"), HasSubstr("expected an endpoint tcp://HOST:PORT")));
  }
}

TEST_F(AdversarialInputTest, ABadControllerIsReportedUnderControllerNotGenome) {
  const std::string scenario = Scenario({{"controller", {{"type", "oscilator"}}}});
  const ProcessResult batch = RunBounded({kBin + "orcs-batch", "run", scenario, "--workers", "1", "--quiet", "--out", Out()});
  ExpectOneLineBadInput(batch);
  EXPECT_THAT(batch.err, HasSubstr(scenario + ": field 'controller.type' expected"));
  EXPECT_THAT(batch.err, Not(HasSubstr("'genome'")));
}

TEST_F(AdversarialInputTest, AMeasuredJointAngleOf1e308DegreesIsRefusedNamingFileAndLine) {
  const std::string run = dir_.Write("run.csv",
                                     "# columns: time,/Sim/Pendulum/Motor/DesiredAngle,/Sim/Pendulum/Motor/DesiredTorque,"
                                     "/Sim/Pendulum/Motor/JointAngle\n"
                                     "0,0,1,0\n0.01,0,1,0.5\n0.02,0,1,1e308\n0.03,0,1,1\n");
  const ProcessResult gap = RunBounded({kBin + "orcs-gap", "--rig", "pendulum", "--measured", run, "--out", Out()});
  ExpectOneLineBadInput(gap);
  EXPECT_THAT(gap.err, AllOf(HasSubstr(run + ":4: column '/Sim/Pendulum/Motor/JointAngle'"),
                             HasSubstr("not a physical joint angle (expected −360…360°)")));
}

// A raw job (no orcs-batch in between) with a time limit that is not a number of seconds: INVALID_INPUT naming the
// field from a real orcs-worker; an infinite limit used to time out at once ("time limit of inf s exceeded").
TEST_F(AdversarialInputTest, ARawJobWithANonFiniteTimeLimitIsInvalidInputNamingTheField) {
  test_support::BrokerProcess broker =
      test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  ASSERT_EQ(broker.error, "");
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", broker.workers, "--heartbeat", "0.1", "--id", "w"});
  nlohmann::json scenario = nlohmann::json::parse(kScenario);
  const std::vector<double> limits = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(),
                                      -1.0, 1e300, 30.0};
  std::vector<v1::Job> jobs;
  for (std::size_t i = 0; i < limits.size(); ++i) {
    v1::Job job;
    job.set_job_id("job-" + std::to_string(i));
    job.set_scenario_json(scenario.dump());
    job.set_genome_json(scenario["genome"].dump());
    job.set_seed(1);
    job.set_time_limit_seconds(limits[i]);
    jobs.push_back(std::move(job));
  }
  const std::map<std::string, v1::Result> results =
      test_support::CollectBatch(broker.clients, std::move(jobs), std::chrono::seconds(60)).results;
  ASSERT_EQ(results.size(), limits.size());
  for (std::size_t i = 0; i + 1 < limits.size(); ++i) {
    SCOPED_TRACE(limits[i]);
    const v1::Result& result = results.at("job-" + std::to_string(i));
    EXPECT_EQ(result.status(), v1::Result::INVALID_INPUT) << result.message();
    EXPECT_THAT(result.message(), AllOf(HasSubstr("job job-" + std::to_string(i)),
                                        HasSubstr("field 'time_limit_seconds' expected seconds from 0 (none) to 1e+09")));
  }
  EXPECT_EQ(results.at("job-4").status(), v1::Result::OK) << results.at("job-4").message();
}

// ---------------------------------------------------------------------------------------------------------
// Issue 47, item 5: counts that allocate in proportion to a number, names that leave runs/, names that cut or
// flood the error line.

// The largest resident set of any child this test process has waited for, bytes (each TEST runs in its own process).
long PeakChildMemoryBytes() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_maxrss * 1024L;
}

TEST_F(AdversarialInputTest, OneBillionParameterSetsAreRefusedNamingTheFieldBeforeAnythingIsAllocated) {
  const std::string scenario = Scenario({{"randomisation", {{"sets", 1000000000}}}});
  const std::string expected =
      scenario + ": field 'randomisation.sets' expected an integer from 1 to 10000, found the number 1000000000";
  const Clock::time_point start = Clock::now();
  const ProcessResult batch = RunBounded({kBin + "orcs-batch", "run", scenario, "--workers", "1", "--quiet", "--out", Out()});
  ExpectOneLineBadInput(batch);
  EXPECT_THAT(batch.err, HasSubstr(expected));  // on main: std::bad_alloc at 3.1 GB, no field named
  const ProcessResult sim = RunBounded({kBin + "orcs-sim", "--scenario", scenario});
  ExpectOneLineBadInput(sim);
  EXPECT_THAT(sim.err, HasSubstr(expected));
  EXPECT_THAT(batch.err + sim.err, Not(HasSubstr("bad_alloc")));
  const long peak = PeakChildMemoryBytes();
  EXPECT_LT(peak, 300L << 20) << "memory must not grow with the number of sets";
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(20));
  std::cout << "figures: sets = 1e9 refused in " << std::chrono::duration_cast<milliseconds>(Clock::now() - start).count()
            << " ms (orcs-batch and orcs-sim), peak child memory " << (peak >> 20) << " MiB\n";

  // A job from any client (no orcs-batch in between) is INVALID_INPUT naming the field, from a real orcs-worker.
  test_support::BrokerProcess broker =
      test_support::StartBrokerProcess({"--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  ASSERT_EQ(broker.error, "");
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", broker.workers, "--heartbeat", "0.1", "--id", "w"});
  nlohmann::json json = nlohmann::json::parse(kScenario);
  json["randomisation"] = {{"sets", 1000000000}};
  v1::Job job;
  job.set_job_id("huge");
  job.set_scenario_json(json.dump());
  job.set_genome_json(json["genome"].dump());
  job.set_seed(1);
  job.set_time_limit_seconds(30);
  std::vector<v1::Job> jobs;
  jobs.push_back(std::move(job));
  const std::map<std::string, v1::Result> results =
      test_support::CollectBatch(broker.clients, std::move(jobs), std::chrono::seconds(60)).results;
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results.at("huge").status(), v1::Result::INVALID_INPUT) << results.at("huge").message();
  EXPECT_THAT(results.at("huge").message(),
              HasSubstr("field 'randomisation.sets' expected an integer from 1 to 10000, found the number 1000000000"));
}

// Runs `argv` in `folder` (through /bin/sh's cd: the default output folder runs/<name> is relative to it).
ProcessResult RunIn(const fs::path& folder, std::vector<std::string> argv) {
  argv.insert(argv.begin(), {"/bin/sh", "-c", "cd \"$0\" && exec \"$@\"", folder.string()});
  return RunBounded(argv);
}

// Every file and folder below `root`, relative to it.
std::vector<std::string> Tree(const fs::path& root) {
  std::vector<std::string> entries;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root)) {
    entries.push_back(fs::relative(entry.path(), root).string());
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

TEST_F(AdversarialInputTest, ANameThatIsAPathANulOr100000CharactersIsRefusedAndNothingIsWrittenOutsideRuns) {
  // orcs-batch runs in home/work; runs/<name> would be home/work/runs/<name>.
  const fs::path home = dir_.path() / "home";
  const fs::path work = home / "work";
  fs::create_directories(work);
  const std::string absolute = (dir_.path() / "absolute-escape").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"../../escaped", "(it contains '/')"},                       // home/escaped, outside runs/ (on main)
      {absolute, "(it contains '/')"},                              // anywhere at all (on main)
      {"..", "(it is '..')"},                                       // runs/.. = the working folder
      {std::string("cut\0here", 8), "\"cut\\x00here\" (it contains a control character)"},  // cut the message at the NUL
      {"two\nlines", "\"two\\nlines\" (it contains a control character)"},
      {std::string(100000, 'n'), "\"" + std::string(80, 'n') + "...\" (it has 100000 bytes)"},  // a 100 kB error line
  };
  for (const auto& [name, found] : cases) {
    SCOPED_TRACE(found);
    const std::string scenario = Scenario({{"name", name}});
    for (const std::string& command : {std::string("run"), std::string("evolve")}) {
      SCOPED_TRACE(command);
      const ProcessResult batch = RunIn(work, {kBin + "orcs-batch", command, scenario, "--workers", "1", "--quiet"});
      ExpectOneLineBadInput(batch);
      EXPECT_THAT(batch.err, AllOf(HasSubstr(scenario + ": field 'name' expected a label of 1 to 128 bytes"),
                                   HasSubstr(found)));
      EXPECT_LT(batch.err.size(), 500u) << "a bounded line";
      EXPECT_EQ(Tree(home), std::vector<std::string>{"work"}) << "nothing written, in runs/ or beside it";
      EXPECT_FALSE(fs::exists(absolute));
    }
  }
  // The same scenario with a plain name runs, into runs/<name> below the working folder: the cases above were
  // refused for their names alone.
  const ProcessResult good =
      RunIn(work, {kBin + "orcs-batch", "run", Scenario({{"name", "plain name"}}), "--workers", "1", "--quiet"});
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_TRUE(fs::exists(work / "runs" / "plain name" / "results.jsonl"));
}

// ---------------------------------------------------------------------------------------------------------
// OSP: items 1, 6 and 7 against a real orcs-osp.

using Bytes = std::vector<std::uint8_t>;

Bytes Init() { return {5, 1, 1}; }

// A UDP socket on 127.0.0.1 that speaks OSP's handshake, written from docs/osp.md alone.
class Udp : public test_support::UdpPeer {
 public:
  // INIT and its ACK within `timeout`: the handler port, or 0 when no ACK came.
  std::uint16_t Handshake(std::uint16_t server, milliseconds timeout = milliseconds(2000)) {
    SendTo(server, Init());
    std::uint16_t from = 0;
    const std::optional<Bytes> ack = Receive(timeout, &from);
    return ack && *ack == Bytes{6, 1, 1, 120} ? from : 0;
  }
};

Bytes Int32(Bytes bytes, std::int32_t value) {
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(value) >> (8 * i)));
  return bytes;
}
Bytes String(Bytes bytes, const std::string& text) {
  bytes.insert(bytes.end(), text.begin(), text.end());
  bytes.push_back(0);
  return bytes;
}
// The next datagram starting with `code` within `timeout`, skipping others (late ACKs, agent entries).
std::optional<Bytes> ExpectCode(Udp& udp, std::uint8_t code, milliseconds timeout = milliseconds(2000)) {
  const Clock::time_point end = Clock::now() + timeout;
  while (Clock::now() < end) {
    std::optional<Bytes> bytes =
        udp.Receive(std::chrono::duration_cast<milliseconds>(end - Clock::now()) + milliseconds(1));
    if (bytes && !bytes->empty() && (*bytes)[0] == code) return bytes;
  }
  return std::nullopt;
}

std::int32_t IntAt(const Bytes& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | bytes.at(at + static_cast<std::size_t>(i));
  return static_cast<std::int32_t>(v);
}

// Whether `process` writes `text` to stderr within `timeout` (err() reads what has arrived, 4 KiB at a time).
bool AwaitErr(BackgroundProcess& process, const std::string& text, milliseconds timeout = milliseconds(5000)) {
  const Clock::time_point end = Clock::now() + timeout;
  std::size_t seen = 0;
  while (process.err().find(text) == std::string::npos) {
    if (Clock::now() > end) return false;
    if (process.err().size() == seen) std::this_thread::sleep_for(milliseconds(10));  // nothing new yet
    seen = process.err().size();
  }
  return true;
}

class AdversarialOspTest : public ::testing::Test {
 protected:
  void Start(const std::string& client_timeout) {
    server_ = std::make_unique<BackgroundProcess>(std::vector<std::string>{
        kBin + "orcs-osp", "-port", "0", "-odcp_port", "0", "--client-timeout", client_timeout});
    const std::optional<std::string> line = server_->ReadLine(milliseconds(10000));
    ASSERT_TRUE(line.has_value()) << server_->err();
    std::smatch match;
    ASSERT_TRUE(std::regex_match(*line, match, std::regex("orcs-osp osp=127\\.0\\.0\\.1:(\\d+)"))) << *line;
    port_ = static_cast<std::uint16_t>(std::stoi(match[1]));
  }
  // A new client is served: it gets an ACK, lists the agents and takes control of agent 1 — within `limit`,
  // retrying its INIT every 100 ms (INITs are datagrams: a refused one gets no answer). The time it took.
  std::optional<milliseconds> ServedWithin(Udp& client, milliseconds limit) {
    const Clock::time_point start = Clock::now();
    std::uint16_t handler = 0;
    while (handler == 0 && Clock::now() - start < limit) handler = client.Handshake(port_, milliseconds(100));
    if (handler == 0) return std::nullopt;
    client.SendTo(handler, Int32({100}, 1));
    const std::optional<Bytes> reply = ExpectCode(client, 101);
    EXPECT_TRUE(reply && reply->size() == 7 && (*reply)[5] == 1) << "control of agent 1";
    return std::chrono::duration_cast<milliseconds>(Clock::now() - start);
  }
  std::unique_ptr<BackgroundProcess> server_;
  std::uint16_t port_ = 0;
};

TEST_F(AdversarialOspTest, SixtyFourSilentInitsFillEverySlotAndANewClientIsServedOnceTheyAreReclaimed) {
  Start("1");
  // 64 throwaway clients that say INIT, get their ACK, and never say anything again (their sockets stay open, so
  // no ICMP tells the gateway they are gone).
  std::vector<std::unique_ptr<Udp>> flood;
  for (int i = 0; i < 64; ++i) {
    flood.push_back(std::make_unique<Udp>());
    ASSERT_NE(flood.back()->Handshake(port_), 0) << "INIT " << i;
  }
  const Clock::time_point full = Clock::now();
  Udp late;
  EXPECT_EQ(late.Handshake(port_, milliseconds(300)), 0) << "every slot is taken: the 65th INIT is ignored";
  // Then a real client is served, within the handshake timeout (1 s) and a tick or two; on main it never was.
  const std::optional<milliseconds> served = ServedWithin(late, milliseconds(10000));
  ASSERT_TRUE(served.has_value()) << server_->err();
  const auto after_full = std::chrono::duration_cast<milliseconds>(Clock::now() - full);
  EXPECT_GE(after_full, milliseconds(1000)) << "not before the timeout";
  EXPECT_LT(after_full, milliseconds(4000));
  std::cout << "figures: 64 silent INITs; a new client served " << after_full.count()
            << " ms after the slots filled (--client-timeout 1)\n";
  EXPECT_TRUE(AwaitErr(*server_, "client(s) sent nothing to their handler port within 1000 ms of their INIT"));
}

TEST_F(AdversarialOspTest, InitsFromSocketsClosedAtOnceAreReclaimedWithoutWaitingForTheTimeout) {
  Start("600");  // a timeout far beyond the test: only "its port is closed" can free the slots
  for (int i = 0; i < 200; ++i) {
    Udp throwaway;
    throwaway.SendTo(port_, Init());
  }  // each closed before its ACK arrives: the ACK draws an ICMP "port unreachable"
  Udp client;
  const std::optional<milliseconds> served = ServedWithin(client, milliseconds(10000));
  ASSERT_TRUE(served.has_value()) << server_->err();
  EXPECT_LT(*served, milliseconds(5000));
  std::cout << "figures: 200 INITs from closed sockets; a new client served after " << served->count() << " ms\n";
  EXPECT_TRUE(AwaitErr(*server_, "is gone (its port is closed: ICMP port unreachable)"));
}

TEST_F(AdversarialOspTest, ClientsThatSpokeThenWentSilentYieldTheirSlotsOnlyWhenTheServerIsFull) {
  Start("1");
  std::vector<std::unique_ptr<Udp>> idle;
  std::vector<std::uint16_t> handlers;
  for (int i = 0; i < 64; ++i) {
    idle.push_back(std::make_unique<Udp>());
    handlers.push_back(idle.back()->Handshake(port_));
    ASSERT_NE(handlers.back(), 0);
    idle.back()->SendTo(handlers.back(), {90});  // agent overview: the handshake is complete
    ASSERT_TRUE(ExpectCode(*idle.back(), 91).has_value());
  }
  // Silent for longer than the timeout with room to spare... there is none: a new INIT takes the slot of the
  // client silent longest, and only once that one has been silent for the timeout.
  Udp late;
  EXPECT_EQ(late.Handshake(port_, milliseconds(200)), 0) << "no client has been silent for 1 s yet";
  const std::optional<milliseconds> served = ServedWithin(late, milliseconds(10000));
  ASSERT_TRUE(served.has_value()) << server_->err();
  EXPECT_TRUE(AwaitErr(*server_, "while every slot was taken: its slot goes to a new client"));
  // The other 63 keep their sessions: the last one still answers.
  idle.back()->SendTo(handlers.back(), {90});
  EXPECT_TRUE(ExpectCode(*idle.back(), 91).has_value());
}

TEST_F(AdversarialOspTest, AnIdleClientKeepsItsSessionWhileThereIsRoom) {
  Start("0.3");
  Udp client;
  const std::uint16_t handler = client.Handshake(port_);
  ASSERT_NE(handler, 0);
  client.SendTo(handler, {90});
  ASSERT_TRUE(ExpectCode(client, 91).has_value());
  // Silent for five timeouts, nobody waiting and room to spare (the time must pass: nothing to await)...
  EXPECT_FALSE(ExpectCode(client, 91, milliseconds(1500)).has_value());
  // ... and still served.
  client.SendTo(handler, {90});
  EXPECT_TRUE(ExpectCode(client, 91).has_value());
}

// Issue 47, item 5: 100,000 one-byte datagrams on the server port made 6.9 MB of stderr in a second, a line each.
// Now the first from each sender is logged and the rest are counted, in one line at the latest when the gateway
// stops; a good client is served all the while.
TEST_F(AdversarialOspTest, AHundredThousandBadDatagramsOnTheServerPortCostAFewLinesAndAGoodClientIsServed) {
  Start("10");
  const std::size_t before = server_->err().size();
  Udp flooder;
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < 100000; ++i) flooder.SendTo(port_, {static_cast<std::uint8_t>(i)});
  const auto sent_in = std::chrono::duration_cast<milliseconds>(Clock::now() - start);
  Udp client;
  const std::optional<milliseconds> served = ServedWithin(client, milliseconds(10000));
  ASSERT_TRUE(served.has_value()) << server_->err().substr(0, 2000);
  EXPECT_TRUE(AwaitErr(*server_, "(further ignored datagrams from it are counted, not logged)"));
  server_->Signal(SIGTERM);  // Run() returns and gives the count of what went unlogged
  const std::optional<ProcessResult> ended = server_->Wait(milliseconds(10000));
  ASSERT_TRUE(ended.has_value());
  const std::string& err = ended->err;
  std::smatch count;
  ASSERT_TRUE(std::regex_search(err, count, std::regex("ignored (\\d+) more datagram\\(s\\) on the server port"))) << err;
  const long unlogged = std::stol(count[1]);
  EXPECT_GT(unlogged, 0);
  EXPECT_LT(err.size() - before, 10000u) << err.substr(0, 2000);
  std::cout << "figures: 100000 one-byte datagrams sent in " << sent_in.count() << " ms; " << unlogged + 1
            << " reached the server port and were ignored; stderr grew " << err.size() - before
            << " bytes; a good client was served after " << served->count() << " ms\n";
}

TEST_F(AdversarialOspTest, ATimeStepOfMinusOneInfOr1e300IsRefusedBySetValueAndTheGatewayServesOn) {
  Start("10");
  Udp client;
  const std::uint16_t handler = client.Handshake(port_);
  ASSERT_NE(handler, 0);
  client.SendTo(handler, String({40}, "/Simulation/TimeStepSize"));
  const std::optional<Bytes> count = client.Receive(milliseconds(2000));
  ASSERT_TRUE(count && (*count)[0] == 41 && IntAt(*count, 1) == 1);
  const std::optional<Bytes> entry = client.Receive(milliseconds(2000));
  ASSERT_TRUE(entry && (*entry)[0] == 43);
  const std::int32_t id = IntAt(*entry, 5);
  for (const char* bad : {"-1", "inf", "1e300", "1e-300", "0"}) {
    SCOPED_TRACE(bad);
    client.SendTo(handler, String(Int32({52}, id), bad));
    const std::optional<Bytes> reply = client.Receive(milliseconds(2000));
    ASSERT_TRUE(reply && (*reply)[0] == 53);
    EXPECT_EQ((*reply)[5], 0) << "refused: the value is unchanged";
  }
  client.SendTo(handler, Int32({50}, id));
  const std::optional<Bytes> value = client.Receive(milliseconds(2000));
  ASSERT_TRUE(value && (*value)[0] == 51);
  EXPECT_EQ(std::string(value->begin() + 5, value->end() - 2), "0.01");
  // And a step still runs (a step with a refused time step would have ended the gateway).
  client.SendTo(handler, Int32({100}, 1));
  ASSERT_TRUE(ExpectCode(client, 101).has_value());
  Bytes step = Int32(Int32({80}, 1), 42);
  for (int i = 0; i < 42; ++i) step = Int32(step, std::bit_cast<std::int32_t>(0.0f));
  client.SendTo(handler, step);
  ASSERT_TRUE(ExpectCode(client, 81).has_value());
  ASSERT_TRUE(ExpectCode(client, 85).has_value()) << server_->err();
}

TEST_F(AdversarialOspTest, AnExponentialPatternInCommand40IsAnsweredPromptlyAndTheGatewayStaysResponsive) {
  Start("10");
  Udp client;
  const std::uint16_t handler = client.Handshake(port_);
  ASSERT_NE(handler, 0);
  const Clock::time_point start = Clock::now();
  client.SendTo(handler, String({40}, kEvilPattern));
  const std::optional<Bytes> count = client.Receive(milliseconds(5000));
  ASSERT_TRUE(count.has_value()) << "no answer within 5 s";
  EXPECT_EQ((*count)[0], 41);
  EXPECT_EQ(IntAt(*count, 1), 0);
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(2));
  // An over-long pattern matches nothing and is logged; a second client is served meanwhile.
  client.SendTo(handler, String({40}, std::string(1001, 'a')));
  const std::optional<Bytes> refused = client.Receive(milliseconds(2000));
  ASSERT_TRUE(refused && (*refused)[0] == 41);
  EXPECT_EQ(IntAt(*refused, 1), 0);
  Udp other;
  EXPECT_NE(other.Handshake(port_), 0);
  EXPECT_TRUE(AwaitErr(*server_, "regular expression of 1001 characters: at most 1000 are accepted"));
}

}  // namespace
}  // namespace orcs
