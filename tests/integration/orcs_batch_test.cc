// orcs-batch as users run it: the real program with its embedded broker and local orcs-worker processes, against
// a running orcs-broker, and its sweep with the plot script; everything on 127.0.0.1. Checks what the output
// folder holds, the exit codes, that bad input stops before anything runs, and that a job replays with
// `orcs-sim --scenario` to the same bits.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "model/evaluation/recording_reader.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::HasSubstr;
using ::testing::MatchesRegex;
using ::testing::Not;

const std::string kBin = ORCS_BINARY_DIR "/bin/";

// Hip oscillators for a fifth of a second under two randomised parameter sets, logging one joint angle.
constexpr const char* kScenario = R"({
  "name": "hips",
  "duration": 0.2,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]},
  "randomisation": {"sets": 2, "default_motor_model": true},
  "log": ["/Sim/Humanoid/Right/HipYaw/JointAngle"],
  "genome": [20, 2, 0, 0, 20, 2, 3, 0]
})";

constexpr const char* kGenomes = "[20, 2, 0, 0, 20, 2, 3, 0]\n[30, 1, 0, 5, 30, 1, 0, -5]\n";

std::vector<nlohmann::json> ReadLines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

std::map<std::string, nlohmann::json> ById(const std::vector<nlohmann::json>& lines) {
  std::map<std::string, nlohmann::json> by_id;
  for (const nlohmann::json& line : lines) by_id[line["id"]] = line;
  return by_id;
}

// A loopback port nothing listens on (bound, then released).
int UnusedPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

class OrcsBatchTest : public ::testing::Test {
 protected:
  ProcessResult Batch(std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), kBin + "orcs-batch");
    return RunProcess(arguments);
  }
  std::string Scenario(const std::string& text = kScenario) { return dir_.Write("hips.json", text); }
  std::string Out(const std::string& name) { return dir_.PathOf(name); }
  TempDir dir_;
};

TEST_F(OrcsBatchTest, RunWritesEveryResultAndLogAndTheSameBitsOnOneWorkerAsOnTwo) {
  const std::string scenario = Scenario();
  const std::string genomes = dir_.Write("genomes.jsonl", kGenomes);
  const ProcessResult two = Batch({"run", scenario, "--genomes", genomes, "--jobs", "3", "--seed", "10",
                                   "--workers", "2", "--out", Out("two")});
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_THAT(two.out, HasSubstr("6 of 6 jobs ran: 6 ok, 0 failed"));
  EXPECT_THAT(two.out, HasSubstr("best fitness"));
  EXPECT_THAT(two.err, HasSubstr("6/6 jobs (ok 6, failed 0)"));  // plain progress lines: stderr is no terminal
  EXPECT_THAT(two.err, Not(HasSubstr("\r")));
  EXPECT_FALSE(fs::exists(Out("two") + "/results.jsonl.partial"));

  const std::vector<nlohmann::json> lines = ReadLines(Out("two") + "/results.jsonl");
  ASSERT_EQ(lines.size(), 6u);
  const std::map<std::string, nlohmann::json> by_id = ById(lines);
  ASSERT_EQ(by_id.size(), 6u) << "no duplicate ids";
  std::set<std::string> workers;
  for (const auto& [id, line] : by_id) {
    EXPECT_EQ(line["status"], "ok") << line["message"];
    EXPECT_TRUE(line["fitness"].is_number());
    EXPECT_EQ(line["sets"].size(), 2u);
    EXPECT_TRUE(line["sets"][0]["drawn"].contains("/AngularMotor/PID/Proportional"));
    EXPECT_TRUE(line["terms"].contains("distance"));
    EXPECT_GT(line["timings"]["run_seconds"].get<double>(), 0.0);
    workers.insert(line["worker"]);
    for (int k = 0; k < 2; ++k) {
      const std::string log = dir_.Read(Out("two") + "/logs/" + id + ".set-" + std::to_string(k) + ".csv");
      EXPECT_THAT(log, HasSubstr("/Sim/Humanoid/Right/HipYaw/JointAngle")) << id;
    }
  }
  EXPECT_EQ(workers.size(), 2u) << "both local workers got jobs";
  EXPECT_EQ(by_id.at("job-4")["seed"], 11);  // genome 1, repeat 1
  EXPECT_EQ(by_id.at("job-4")["genome_index"], 1);

  const ProcessResult one = Batch({"run", scenario, "--genomes", genomes, "--jobs", "3", "--seed", "10",
                                   "--workers", "1", "--out", Out("one"), "--quiet"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.err, "");  // --quiet
  for (const auto& [id, line] : ById(ReadLines(Out("one") + "/results.jsonl"))) {
    EXPECT_EQ(line["fitness"].dump(), by_id.at(id)["fitness"].dump()) << id;  // the same text: the same bits
    EXPECT_EQ(line["sets"].dump(), by_id.at(id)["sets"].dump()) << id;
  }
}

TEST_F(OrcsBatchTest, AJobReplaysWithOrcsSimToTheSameBits) {
  const std::string scenario = Scenario();
  const ProcessResult batch = Batch({"run", scenario, "--seed", "42", "--workers", "1", "--out", Out("b")});
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  const nlohmann::json line = ReadLines(Out("b") + "/results.jsonl").at(0);
  const ProcessResult sim = RunProcess({kBin + "orcs-sim", "--scenario", scenario, "--seed", "42"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const nlohmann::json replay = nlohmann::json::parse(sim.out);
  EXPECT_EQ(replay["fitness"].dump(), line["fitness"].dump());
  EXPECT_EQ(replay["sets"].dump(), line["sets"].dump());
}

// run --engine MuJoCo: every job runs on MuJoCo (results.jsonl says so) and orcs-sim --engine MuJoCo replays a
// job to the same bits; without the option the same jobs run on the scenario's engine, ODE.
TEST_F(OrcsBatchTest, RunOnMujocoNamesTheEngineAndAJobReplaysWithOrcsSimOnIt) {
  const std::string scenario = Scenario();
  const ProcessResult mujoco =
      Batch({"run", scenario, "--seed", "42", "--jobs", "2", "--engine", "MuJoCo", "--workers", "2", "--out", Out("m")});
  ASSERT_EQ(mujoco.exit_code, 0) << mujoco.err;
  const std::vector<nlohmann::json> lines = ReadLines(Out("m") + "/results.jsonl");
  ASSERT_EQ(lines.size(), 2u);
  for (const nlohmann::json& line : lines) EXPECT_EQ(line["engine"], "MuJoCo") << line.dump();
  const nlohmann::json first = ById(lines).at("job-0");
  const ProcessResult sim =
      RunProcess({kBin + "orcs-sim", "--scenario", scenario, "--seed", "42", "--engine", "MuJoCo"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(nlohmann::json::parse(sim.out)["sets"].dump(), first["sets"].dump());

  const ProcessResult ode = Batch({"run", scenario, "--seed", "42", "--workers", "1", "--out", Out("o"), "--quiet"});
  ASSERT_EQ(ode.exit_code, 0) << ode.err;
  const nlohmann::json ode_line = ReadLines(Out("o") + "/results.jsonl").at(0);
  EXPECT_EQ(ode_line["engine"], "ODE");
  EXPECT_NE(ode_line["sets"].dump(), first["sets"].dump());
  const ProcessResult unknown = Batch({"run", scenario, "--engine", "Bullet", "--out", Out("x")});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_THAT(unknown.err, HasSubstr("--engine: Bullet not in {ODE,MuJoCo}"));

  // compare (issue 21 item 5): job-0 on both engines differs, job-1 ran only on MuJoCo; a run against itself is
  // unchanged. Exit 1 and 0, as diff's.
  const ProcessResult compared = Batch({"compare", Out("m"), Out("o"), "--out", Out("cmp")});
  EXPECT_EQ(compared.exit_code, 1) << compared.err;
  EXPECT_THAT(compared.out, HasSubstr("1 jobs in both (matched by seed and genome), 1 changed (any bit); 1 only in A, 0 only in B"));
  EXPECT_THAT(compared.out, HasSubstr("job-0: fitness "));
  EXPECT_THAT(compared.out, HasSubstr("job-1: only in A"));
  EXPECT_EQ(dir_.Read(Out("cmp") + "/compare.png").substr(1, 3), "PNG");
  EXPECT_THAT(dir_.Read(Out("cmp") + "/compare.csv"), HasSubstr("job-0,ok,ok,"));
  const ProcessResult same = Batch({"compare", Out("o"), Out("o") + "/results.jsonl", "--out", Out("cmp"), "--no-plot"});
  EXPECT_EQ(same.exit_code, 0) << same.err;
  EXPECT_THAT(same.out, HasSubstr("1 jobs in both (matched by seed and genome), 0 changed"));
}

TEST_F(OrcsBatchTest, BadInputStopsBeforeAnythingRunsWithTheFileNamed) {
  const std::string scenario = Scenario();
  const std::string genomes = dir_.Write("genomes.jsonl", "[20, 2, 0, 0, 20, 2, 3, 0]\n[1, 2, 3]\n");
  ProcessResult result = Batch({"run", scenario, "--genomes", genomes, "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("genomes.jsonl:2: field 'genome' expected 8 numbers, found an array of 3"));
  EXPECT_FALSE(fs::exists(Out("bad"))) << "nothing written, nothing submitted";

  const std::string typo = dir_.Write("typo.json", R"({"controller": {"type": "oscillator", "joints": []},
      "fitness": {"terms": []}, "randomisation": {"sets": 2, "parameters": [{"path": "/X", "uniform": [2, 1]}]}})");
  result = Batch({"run", typo, "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("typo.json"));
  EXPECT_THAT(result.err, HasSubstr("randomisation.parameters[0]"));

  result = Batch({"sweep", scenario, "--param", "/AngularMotor/PID/Proportional=30:10:3", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("LOW 30 is above HIGH 10"));

  result = Batch({"run", scenario, "--jobs", "0"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("--jobs"));
  EXPECT_FALSE(fs::exists(Out("bad")));
}

TEST_F(OrcsBatchTest, ResolvePrintsTheScenarioWithEveryFileInlined) {
  const std::string examples = ORCS_SOURCE_DIR "/scenarios/examples/";
  ProcessResult result = Batch({"resolve", examples + "pendulum_keyframes.json"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  const nlohmann::json resolved = nlohmann::json::parse(result.out);  // one JSON document and nothing else
  EXPECT_EQ(resolved["name"], "pendulum-keyframes");
  EXPECT_EQ(resolved["environment"]["file"], "../environments/pendulum.xml");
  EXPECT_EQ(resolved["environment"]["xml"], dir_.Read(ORCS_SOURCE_DIR "/scenarios/environments/pendulum.xml"));
  const std::string record = dir_.Read(examples + "pendulum_quarter.csv");
  ASSERT_FALSE(record.empty());
  EXPECT_EQ(resolved["controller"]["record"]["text"], record);
  EXPECT_EQ(resolved["fitness"]["terms"][0]["record"]["text"], record);

  // A value file the scenario names is inlined too; one it cannot read is bad input naming it.
  dir_.Write("motor.val", "/AngularMotor/PID/Proportional=18\n");
  nlohmann::json with_values = nlohmann::json::parse(kScenario);
  with_values["value_files"] = {"motor.val"};
  result = Batch({"resolve", dir_.Write("values.json", with_values.dump())});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json assignment = nlohmann::json::parse(result.out)["value_files"][0]["assignments"][0];
  EXPECT_EQ(assignment[0], "/AngularMotor/PID/Proportional");
  EXPECT_EQ(assignment[1], "18");
  with_values["value_files"] = {"missing.val"};
  result = Batch({"resolve", dir_.Write("missing.json", with_values.dump())});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.out, "");
  EXPECT_THAT(result.err, HasSubstr("missing.val"));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST_F(OrcsBatchTest, FailedJobsGiveExitCodeOneAndTheirStatus) {
  nlohmann::json slow = nlohmann::json::parse(kScenario);
  slow["duration"] = 1000;
  const std::string scenario = dir_.Write("slow.json", slow.dump());
  const ProcessResult result = Batch({"run", scenario, "--jobs", "2", "--time-limit", "0.05", "--workers", "2",
                                      "--out", Out("slow")});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_THAT(result.out, HasSubstr("0 ok, 2 failed (timeout 2)"));
  for (const nlohmann::json& line : ReadLines(Out("slow") + "/results.jsonl")) {
    EXPECT_EQ(line["status"], "timeout");
    EXPECT_TRUE(line["fitness"].is_null());
    EXPECT_THAT(line["message"].get<std::string>(), HasSubstr("time limit"));
  }
}

TEST_F(OrcsBatchTest, SubmitRunsTheBatchOnARunningBroker) {
  BackgroundProcess broker({kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  const std::optional<std::string> endpoints = broker.ReadLine(milliseconds(10000));
  ASSERT_TRUE(endpoints.has_value()) << broker.err();
  std::smatch match;
  const std::regex pattern("orcs-broker clients=(\\S+) workers=(\\S+)");
  ASSERT_TRUE(std::regex_match(*endpoints, match, pattern)) << *endpoints;
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", match[2], "--heartbeat", "0.1", "--id", "remote"});
  const ProcessResult result = Batch({"submit", "--broker", match[1], "--heartbeat", "0.1", Scenario(), "--jobs", "3",
                                      "--out", Out("remote")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<nlohmann::json> lines = ReadLines(Out("remote") + "/results.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  for (const nlohmann::json& line : lines) EXPECT_EQ(line["worker"], "remote");
  // progress.json for orcs-view: the end, the counts, and the broker's batch id (the dashboard's key to the
  // folder's recordings).
  const nlohmann::json progress = nlohmann::json::parse(dir_.Read(Out("remote") + "/progress.json"));
  EXPECT_EQ(progress["command"], "submit");
  EXPECT_EQ(progress["state"], "finished");
  EXPECT_EQ(progress["done"], 3);
  EXPECT_EQ(progress["total"], 3);
  EXPECT_THAT(progress["broker_batch"].get<std::string>(), MatchesRegex("[0-9a-f]{32}"));
}

// A broker at a fast pace (--heartbeat 0.1: peers silent for 0.5 s are lost) and a worker and a client left at the
// default 1 s: each side says its pace, and the broker waits for the slower one. Before, the broker dropped the
// client every 0.5 s and the client submitted its batch again, for ever.
TEST_F(OrcsBatchTest, ABrokerFasterThanItsWorkerAndClientLosesNeither) {
  BackgroundProcess broker({kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  const std::optional<std::string> endpoints = broker.ReadLine(milliseconds(10000));
  ASSERT_TRUE(endpoints.has_value()) << broker.err();
  std::smatch match;
  ASSERT_TRUE(std::regex_match(*endpoints, match, std::regex("orcs-broker clients=(\\S+) workers=(\\S+)")));
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", match[2], "--id", "steady"});
  const ProcessResult result =
      Batch({"submit", "--broker", match[1], Scenario(), "--jobs", "8", "--out", Out("paced"), "--quiet"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(ReadLines(Out("paced") + "/results.jsonl").size(), 8u);
  broker.Signal(SIGTERM);
  ASSERT_TRUE(broker.Wait(milliseconds(10000)).has_value());
  const std::string log = broker.err();
  EXPECT_THAT(log, Not(HasSubstr(" lost"))) << log;
  std::size_t opened = 0;
  for (std::size_t at = log.find("opened batch"); at != std::string::npos; at = log.find("opened batch", at + 1)) {
    ++opened;
  }
  EXPECT_EQ(opened, 1u) << "the batch was submitted again: " << log;
}

// The channel of `name` (x, y or z of a vector) in the last frame.
float LastValue(const evaluation::Recording& recording, const std::string& name) {
  const int channel = recording.FindChannel(name);
  EXPECT_GE(channel, 0) << name;
  return channel < 0 ? std::nanf("") : recording.value(recording.frame_count() - 1, channel);
}

TEST_F(OrcsBatchTest, RecordedJobsThroughARunningBrokerAreWrittenWithTheSameBitsAndReplayWithOrcsSim) {
  BackgroundProcess broker({kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  const std::optional<std::string> endpoints = broker.ReadLine(milliseconds(10000));
  ASSERT_TRUE(endpoints.has_value()) << broker.err();
  std::smatch match;
  ASSERT_TRUE(std::regex_match(*endpoints, match, std::regex("orcs-broker clients=(\\S+) workers=(\\S+)")));
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", match[2], "--heartbeat", "0.1", "--id", "remote"});
  // Three identical jobs (one genome three times, one seed): 0 and 2 recorded, 1 not.
  const std::string genome = "[20, 2, 0, 0, 20, 2, 3, 0]";
  const std::string genomes = dir_.Write("same.jsonl", genome + "\n" + genome + "\n" + genome + "\n");
  dir_.Write("rec/recordings/job-7.orcsrec", "an earlier batch's");
  const std::string scenario = Scenario();
  const ProcessResult result = Batch({"submit", "--broker", match[1], "--heartbeat", "0.1", scenario, "--genomes",
                                      genomes, "--seed", "5", "--record", "0,2", "--out", Out("rec")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::map<std::string, nlohmann::json> by_id = ById(ReadLines(Out("rec") + "/results.jsonl"));
  ASSERT_EQ(by_id.size(), 3u);
  EXPECT_EQ(by_id.at("job-0")["recording"], "recordings/job-0.orcsrec");
  EXPECT_FALSE(by_id.at("job-1").contains("recording"));
  EXPECT_EQ(by_id.at("job-2")["recording"], "recordings/job-2.orcsrec");
  std::set<std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(Out("rec") + "/recordings")) {
    files.insert(entry.path().filename().string());
  }
  EXPECT_EQ(files, (std::set<std::string>{"job-0.orcsrec", "job-2.orcsrec"})) << "exactly those, the stale one gone";
  for (const char* id : {"job-1", "job-2"}) {  // recorded or not: the same bits
    EXPECT_EQ(by_id.at(id)["fitness"].dump(), by_id.at("job-0")["fitness"].dump()) << id;
    EXPECT_EQ(by_id.at(id)["sets"].dump(), by_id.at("job-0")["sets"].dump()) << id;
  }

  const evaluation::Recording recording = evaluation::ReadRecording(Out("rec") + "/recordings/job-0.orcsrec");
  const double step = recording.header["step_seconds"].get<double>();
  EXPECT_EQ(recording.frame_count(), std::lround(0.2 / step) + 1);  // frame 0 and one per step
  EXPECT_EQ(recording.header["source"]["seed"], 5);
  EXPECT_EQ(recording.header["source"]["set"], 0);
  const ProcessResult sim = RunProcess({kBin + "orcs-sim", "--scenario", scenario, "--genome", genome, "--seed", "5",
                                        "--record", Out("sim.orcsrec")});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(nlohmann::json::parse(sim.out)["fitness"].dump(), by_id.at("job-0")["fitness"].dump());
  const evaluation::Recording replay = evaluation::ReadRecording(Out("sim.orcsrec"));
  ASSERT_EQ(replay.frame_count(), recording.frame_count());
  for (const char* axis : {".x", ".y", ".z"}) {
    const std::string channel = std::string("/Sim/Humanoid/Middle/Head/Position") + axis;
    const float batch = LastValue(recording, channel);
    const float local = LastValue(replay, channel);
    EXPECT_EQ(std::memcmp(&batch, &local, sizeof batch), 0) << channel << ": " << batch << " vs " << local;
  }
}

TEST_F(OrcsBatchTest, AScenarioThatAsksForRecordingsGetsEveryJobRecordedAndBadRecordTextIsExitTwo) {
  nlohmann::json recorded = nlohmann::json::parse(kScenario);
  recorded["record"] = true;
  recorded["duration"] = 0.05;
  const std::string scenario = dir_.Write("recorded.json", recorded.dump());
  ProcessResult result = Batch({"run", scenario, "--jobs", "2", "--workers", "1", "--out", Out("all"), "--quiet"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* id : {"job-0", "job-1"}) {
    EXPECT_NO_THROW(evaluation::ReadRecording(Out("all") + "/recordings/" + id + ".orcsrec")) << id;
  }

  for (const char* bad : {"1-x", "0,5", "everything"}) {
    result = Batch({"run", Scenario(), "--jobs", "3", "--record", bad, "--out", Out("bad")});
    EXPECT_EQ(result.exit_code, 2) << bad;
    EXPECT_THAT(result.err, HasSubstr("--record")) << bad;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_FALSE(fs::exists(Out("bad"))) << "nothing written, nothing submitted";
  }
  recorded["record"] = "yes";
  result = Batch({"run", dir_.Write("yes.json", recorded.dump()), "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("yes.json: field 'record' expected true or false, found the string \"yes\""));
}

TEST_F(OrcsBatchTest, AnUnreachableBrokerIsAClearErrorNotAHang) {
  const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(UnusedPort());
  const ProcessResult result = Batch({"submit", "--broker", endpoint, Scenario(), "--out", Out("none")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr(endpoint));
}

TEST_F(OrcsBatchTest, SweepWritesATableACsvAndAPlot) {
  const ProcessResult result =
      Batch({"sweep", Scenario(), "--param", "/AngularMotor/PID/Proportional=10:20:2", "--param",
             "/Simulation/ODE/FrictionScaling=0.8:1.2:3", "--jobs", "2", "--workers", "2", "--out", Out("sweep")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("PID/Proportional"));
  EXPECT_THAT(result.out, HasSubstr("12 of 12 jobs ran: 12 ok"));
  const std::string csv = dir_.Read(Out("sweep") + "/sweep.csv");
  std::istringstream rows(csv);
  std::string row;
  std::vector<std::string> all;
  while (std::getline(rows, row)) all.push_back(row);
  ASSERT_EQ(all.size(), 7u) << csv;  // header + 2 × 3 points
  EXPECT_EQ(all[0], "/AngularMotor/PID/Proportional,/Simulation/ODE/FrictionScaling,fitness,min_fitness,max_fitness,ok,jobs");
  EXPECT_EQ(all[6].substr(0, 7), "20,1.2,");
  EXPECT_EQ(all[6].substr(all[6].size() - 4), ",2,2");
  // The sweep changes what it says it changes: the gain's two values give different fitness (same seeds).
  std::set<std::string> fitness_by_gain[2];
  for (const nlohmann::json& line : ReadLines(Out("sweep") + "/results.jsonl")) {
    const double gain = line["params"]["/AngularMotor/PID/Proportional"];
    fitness_by_gain[gain == 10 ? 0 : 1].insert(line["fitness"].dump());
  }
  for (const std::string& fitness : fitness_by_gain[0]) EXPECT_FALSE(fitness_by_gain[1].contains(fitness));

  const ProcessResult plot = RunProcess({"/usr/bin/python3", ORCS_SOURCE_DIR "/scripts/plot_sweep.py", Out("sweep")});
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  EXPECT_EQ(dir_.Read(Out("sweep") + "/sweep.png").substr(1, 3), "PNG");
}

// A body of the robot as a sweep axis (issue 48): two masses of the right foot, through the real broker and
// workers, give two fitness values for the same seeds; both points' jobs ran ok.
// A body's mass as a numeric axis and a sole pad's material as a categorical one (issue 48): every point differs.
TEST_F(OrcsBatchTest, ASweepOverAFootsMassAndItsSolePadsMaterialChangesTheFitness) {
  const std::string mass = "/Sim/Humanoid/Right/Foot/Mass", material = "/Sim/Humanoid/Right/Foot/RightSolePadHeel/Material";
  const ProcessResult result = Batch({"sweep", Scenario(), "--param", mass + "=0.05:0.6:2", "--param",
                                      material + "=Latex,Wood", "--workers", "2", "--out", Out("feet")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("4 of 4 jobs ran: 4 ok"));
  std::map<std::pair<double, std::string>, std::string> fitness;
  for (const nlohmann::json& line : ReadLines(Out("feet") + "/results.jsonl")) {
    fitness[{line["params"][mass].get<double>(), line["params"][material].get<std::string>()}] = line["fitness"].dump();
  }
  ASSERT_EQ(fitness.size(), 4u);
  EXPECT_NE(fitness.at({0.05, "Latex"}), fitness.at({0.6, "Latex"})) << "the mass";
  EXPECT_NE(fitness.at({0.05, "Latex"}), fitness.at({0.05, "Wood"})) << "the material";
}

// A robot from a file runs through the real broker and workers (issue 48): the scenario's environment names the
// shipped long-shinned A-Series, the client sends it inline, and its jobs differ from the built-in robot's.
TEST_F(OrcsBatchTest, ARobotFromAFileRunsInABatchThroughTheBroker) {
  nlohmann::json long_shins = nlohmann::json::parse(kScenario);
  long_shins["environment"] = ORCS_SOURCE_DIR "/scenarios/environments/long_shins.xml";
  const ProcessResult tall = Batch({"run", dir_.Write("tall.json", long_shins.dump()), "--seed", "3", "--workers", "2",
                                    "--out", Out("tall")});
  ASSERT_EQ(tall.exit_code, 0) << tall.err;
  EXPECT_THAT(tall.out, HasSubstr("1 of 1 jobs ran: 1 ok"));
  const ProcessResult plain = Batch({"run", Scenario(), "--seed", "3", "--workers", "1", "--out", Out("plain")});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(ReadLines(Out("tall") + "/results.jsonl").at(0)["fitness"].dump(),
            ReadLines(Out("plain") + "/results.jsonl").at(0)["fitness"].dump());
}

std::vector<std::vector<std::string>> CsvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    rows.push_back(std::move(fields));
  }
  return rows;
}

TEST_F(OrcsBatchTest, ALatinHypercubeSweepWithAFloorMaterialWritesTheRobustnessReportAndAPlot) {
  const ProcessResult result =
      Batch({"sweep", Scenario(), "--sample", "lhs", "--samples", "6", "--param",
             "/AngularMotor/PID/Proportional=10:22", "--param", "/Sim/Floor/Material=PVC,Light,Carpet", "--sample-seed",
             "9", "--workers", "2", "--out", Out("lhs")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("6 of 6 jobs ran: 6 ok"));
  EXPECT_THAT(result.out, HasSubstr("orcs-batch: fitness over 6 of 6 points: mean "));
  EXPECT_THAT(result.out, HasSubstr("orcs-batch: fitness most sensitive to /"));

  // sweep.csv: one row per sample; the gain once in each of the 6 strata of width 2, each floor twice.
  const std::vector<std::vector<std::string>> csv = CsvRows(dir_.Read(Out("lhs") + "/sweep.csv"));
  ASSERT_EQ(csv.size(), 7u);
  EXPECT_EQ(csv[0], (std::vector<std::string>{"/AngularMotor/PID/Proportional", "/Sim/Floor/Material", "fitness",
                                              "min_fitness", "max_fitness", "ok", "jobs"}));
  std::set<int> strata;
  std::map<std::string, int> floors;
  for (std::size_t r = 1; r < csv.size(); ++r) {
    const double gain = std::stod(csv[r][0]);
    strata.insert(static_cast<int>((gain - 10.0) / 2.0));
    ++floors[csv[r][1]];
    EXPECT_EQ(csv[r][5], "1");
  }
  EXPECT_EQ(strata, (std::set<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(floors, (std::map<std::string, int>{{"Carpet", 2}, {"Light", 2}, {"PVC", 2}}));
  for (const nlohmann::json& line : ReadLines(Out("lhs") + "/results.jsonl")) {
    EXPECT_TRUE(line["params"]["/Sim/Floor/Material"].is_string());
  }

  const nlohmann::json report = nlohmann::json::parse(dir_.Read(Out("lhs") + "/robustness.json"));
  EXPECT_EQ(report["sampling"], "lhs");
  EXPECT_EQ(report["points"], 6);
  EXPECT_EQ(report["ok_points"], 6);
  EXPECT_LE(report["fitness"]["min"].get<double>(), report["fitness"]["median"].get<double>());
  EXPECT_EQ(report["worst"]["fitness"], report["fitness"]["min"]);
  ASSERT_EQ(report["sensitivity"].size(), 2u);
  EXPECT_EQ(report["sensitivity"][1]["kind"], "categorical");
  EXPECT_EQ(report["sensitivity"][1]["bins"].size(), 3u);
  EXPECT_EQ(report["ranking"].size(), 2u);
  EXPECT_THAT(dir_.Read(Out("lhs") + "/robustness.md"), HasSubstr("most sensitive to"));

  const ProcessResult plot = RunProcess({"/usr/bin/python3", ORCS_SOURCE_DIR "/scripts/plot_sweep.py", Out("lhs")});
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  EXPECT_EQ(dir_.Read(Out("lhs") + "/sweep.png").substr(1, 3), "PNG");
}

TEST_F(OrcsBatchTest, AGridOverFloorMaterialsReachesTheFloor) {
  nlohmann::json one_set = nlohmann::json::parse(kScenario);
  one_set["randomisation"] = {{"sets", 1}};
  const ProcessResult result = Batch({"sweep", dir_.Write("one.json", one_set.dump()), "--param",
                                      "/Sim/Floor/Material=PVC,Light", "--workers", "1", "--out", Out("floors")});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("Light"));
  std::map<std::string, std::string> terms;
  for (const nlohmann::json& line : ReadLines(Out("floors") + "/results.jsonl")) {
    terms[line["params"]["/Sim/Floor/Material"]] = line["terms"].dump();
  }
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_NE(terms["PVC"], terms["Light"]) << "a frictionless floor moves the robot differently";
}

TEST_F(OrcsBatchTest, BadSamplingInputStopsBeforeAnythingRuns) {
  const std::string scenario = Scenario();
  ProcessResult result = Batch({"sweep", scenario, "--param", "/Sim/Floor/Material=PVC,Wod", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("--param '/Sim/Floor/Material=PVC,Wod': 'Wod' is not a material"));
  result = Batch({"sweep", scenario, "--sample", "lhs", "--param", "/X=1:2", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("--samples"));
  result = Batch({"sweep", scenario, "--samples", "5", "--param", "/X=1:2:2", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("needs --sample lhs"));
  result = Batch({"sweep", scenario, "--sample", "lhs", "--samples", "5", "--param",
                  "/AngularMotor/PID/Proportional=10:20:3", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("--param '/AngularMotor/PID/Proportional=10:20:3': expected LOW:HIGH"));
  result = Batch({"sweep", scenario, "--sample", "lhs", "--samples", "2", "--param",
                  "/Sim/Floor/Material=PVC,Wood,Carpet", "--out", Out("bad")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("every value needs at least one sample"));
  EXPECT_FALSE(fs::exists(Out("bad"))) << "nothing written, nothing submitted";
}

TEST_F(OrcsBatchTest, ThePlotScriptNamesABadSweepFileLine) {
  dir_.Write("bad/sweep.csv", "/A,fitness,min_fitness,max_fitness,ok,jobs\n1,2,3\n");
  const ProcessResult plot = RunProcess({"/usr/bin/python3", ORCS_SOURCE_DIR "/scripts/plot_sweep.py", Out("bad")});
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_THAT(plot.err, HasSubstr("sweep.csv:2: expected 6 fields, found 3"));
}

}  // namespace
}  // namespace orcs
