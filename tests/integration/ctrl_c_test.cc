// Issue 47 item 2: every command stops cleanly on Ctrl-C. The real orcs-batch with its embedded broker and two local
// orcs-worker processes is started as a shell starts a foreground job — leader of its own process group — and gets
// SIGINT sent to that whole group, as a terminal's ^C does (kill(-pgid)). Before the fix the workers, in the same
// group, got it too and left, and evolve waited for ever for a generation nobody ran.
//  - One Ctrl-C: the command exits 130 within 5 s, progress.json says "interrupted", stderr names the exact resume
//    command, no worker of the run is left, and that command finishes the run with the bits of an uninterrupted one.
//  - A second Ctrl-C while the first is being handled (it waits for a worker that does not answer): exit within
//    1 s of it, nothing left running, and the folder still resumes to the same bits.
//  - orcs-gap, which has no resume: exit 130 within 5 s, saying so.
// The waits are on conditions (a file's lines, a progress field) with deadlines, never fixed sleeps.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

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
using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;

const std::string kBatch = ORCS_BINARY_DIR "/bin/orcs-batch";
const std::string kGap = ORCS_BINARY_DIR "/bin/orcs-gap";
const std::string kMotions = ORCS_SOURCE_DIR "/scenarios/motions/";
constexpr int kExitInterrupted = 130;

// The A-Series swinging its hips for `duration` simulated seconds under two drawn parameter sets, with an evolution
// section for `evolve`: CMA-ES over the oscillator's 8 genes, 6 genomes a generation, generations 0 to 2. Short
// jobs keep the whole program near 30 s on 2 busy cores (a 0.2 s job takes about 0.5 s there).
std::string Scenario(double duration) {
  nlohmann::json scenario = nlohmann::json::parse(R"({
  "name": "ctrl-c-test",
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "genome": [10.0, 1.0, 0.0, 0.0, 10.0, 1.0, 3.0, 0.0],
  "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}]},
  "randomisation": {"sets": 2, "default_motor_model": true},
  "evolution": {
    "bounds": [[0, 20], [0.5, 2], [-1, 1], [-1, 1], [0, 20], [0.5, 2], [0, 6], [-1, 1]],
    "algorithm": "cmaes", "population": 6, "generations": 2, "seed": 1, "validate": 0
  }
})");
  scenario["duration"] = duration;
  return scenario.dump(1);
}

std::string ReadIfThere(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::optional<nlohmann::json> Progress(const std::string& folder) {
  const std::string text = ReadIfThere(folder + "/progress.json");
  if (text.empty()) return std::nullopt;
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

// Each job's results.jsonl line without what depends on the run rather than the job (batch_resume_test's way).
std::map<std::string, nlohmann::json> ByJob(const std::vector<std::string>& lines) {
  std::map<std::string, nlohmann::json> jobs;
  for (const std::string& line : lines) {
    nlohmann::json json = nlohmann::json::parse(line);
    for (const char* run_dependent : {"worker", "timings", "attempts"}) json.erase(run_dependent);
    jobs[json["id"].get<std::string>()] = json;
  }
  return jobs;
}

// fitness.csv without its last column (seconds: wall clock, not part of the search).
std::vector<std::string> WithoutSeconds(const std::string& csv) {
  std::vector<std::string> lines = Lines(csv);
  for (std::string& line : lines) line = line.substr(0, line.rfind(','));
  return lines;
}

// One process as /proc shows it.
struct ProcInfo {
  pid_t pid = 0;
  pid_t ppid = 0;
  pid_t pgrp = 0;
  char state = '?';
  std::string comm;
  unsigned long long start_time = 0;  // clock ticks after boot: tells a reused pid apart
};

std::optional<ProcInfo> ReadProc(pid_t pid) {
  const std::string stat = ReadIfThere("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t open = stat.find('('), close = stat.rfind(')');
  if (open == std::string::npos || close == std::string::npos) return std::nullopt;
  ProcInfo info;
  info.pid = pid;
  info.comm = stat.substr(open + 1, close - open - 1);
  std::istringstream rest(stat.substr(close + 2));
  std::vector<std::string> fields;
  for (std::string field; rest >> field;) fields.push_back(field);
  if (fields.size() < 20) return std::nullopt;
  info.state = fields[0][0];
  info.ppid = std::stoi(fields[1]);
  info.pgrp = std::stoi(fields[2]);
  info.start_time = std::stoull(fields[19]);  // field 22 of stat; fields[0] is field 3
  return info;
}

std::vector<ProcInfo> AllProcesses() {
  std::vector<ProcInfo> all;
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::optional<ProcInfo> info = ReadProc(std::stoi(name))) all.push_back(*info);
  }
  return all;
}

// The orcs-worker processes `parent` started, and theirs (simulation processes), once `count` workers are there.
std::vector<ProcInfo> WorkersOf(pid_t parent, std::size_t count) {
  const Clock::time_point deadline = Clock::now() + milliseconds(20000);
  while (Clock::now() < deadline) {
    std::vector<ProcInfo> all = AllProcesses();
    std::vector<ProcInfo> workers;
    for (const ProcInfo& p : all) {
      if (p.ppid == parent && p.comm == "orcs-worker") workers.push_back(p);
    }
    if (workers.size() >= count) {
      for (const ProcInfo& p : all) {
        for (std::size_t w = 0; w < count; ++w) {
          if (p.ppid == workers[w].pid) workers.push_back(p);
        }
      }
      return workers;
    }
    ::usleep(20000);
  }
  return {};
}

// Whether `p` still runs: the same process (pid and start time) and not a zombie.
bool StillRuns(const ProcInfo& p) {
  const std::optional<ProcInfo> now = ReadProc(p.pid);
  return now && now->start_time == p.start_time && now->state != 'Z' && now->state != 'X';
}

// Waits (bounded) for `condition`, while `process` runs; false when it ended first or the deadline passed.
bool AwaitWhileRunning(BackgroundProcess& process, const std::function<bool()>& condition,
                       milliseconds limit = milliseconds(60000)) {
  const Clock::time_point deadline = Clock::now() + limit;
  while (Clock::now() < deadline) {
    if (condition()) return true;
    if (process.Wait(milliseconds(20)).has_value()) return false;
  }
  return false;
}

// Kills a process group when it goes out of scope, if its leader still runs.
class KilledAtTheEnd {
 public:
  explicit KilledAtTheEnd(ProcInfo leader) : leader_(leader) {}
  ~KilledAtTheEnd() {
    if (StillRuns(leader_)) ::kill(-leader_.pgrp, SIGKILL);
  }
  KilledAtTheEnd(const KilledAtTheEnd&) = delete;
  KilledAtTheEnd& operator=(const KilledAtTheEnd&) = delete;

 private:
  ProcInfo leader_;
};

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

class CtrlCTest : public ::testing::Test {
 protected:
  std::string Out(const std::string& name) const { return dir_.PathOf(name); }

  // Every process of the run but the command itself: its workers, in their own process groups (so that the
  // terminal's ^C does not reach them), and their simulation processes.
  std::vector<ProcInfo> ExpectWorkersInTheirOwnGroups(const BackgroundProcess& command) {
    const std::vector<ProcInfo> workers = WorkersOf(command.pid(), 2);
    EXPECT_GE(workers.size(), 2u) << "the run's two local workers";
    for (const ProcInfo& worker : workers) {
      EXPECT_NE(worker.pgrp, command.pid()) << "worker " << worker.pid << " is in the terminal's process group";
    }
    return workers;
  }

  void ExpectNoneLeft(const std::vector<ProcInfo>& workers) {
    // Reaped by their parent before it exits, or killed with it: none may outlive it. A moment for the kernel.
    const Clock::time_point deadline = Clock::now() + milliseconds(1000);
    for (const ProcInfo& worker : workers) {
      while (StillRuns(worker) && Clock::now() < deadline) ::usleep(10000);
      EXPECT_FALSE(StillRuns(worker)) << worker.comm << " " << worker.pid << " outlived the command";
    }
  }

  test_support::TempDir dir_;
};

TEST_F(CtrlCTest, RunStopsOnOneCtrlCToItsGroupWithinFiveSecondsAndItsResumeCommandGivesTheUninterruptedBits) {
  const std::string scenario = dir_.Write("s.json", Scenario(0.3));
  const std::vector<std::string> batch = {kBatch, "run", scenario, "--jobs", "10", "--workers", "2", "--quiet"};
  std::vector<std::string> whole = batch;
  whole.insert(whole.end(), {"--out", Out("whole")});
  const ProcessResult uninterrupted = RunProcess(whole);
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;

  std::vector<std::string> cut = batch;
  cut.insert(cut.end(), {"--out", Out("cut")});
  BackgroundProcess command(cut, /*own_process_group=*/true);
  const std::vector<ProcInfo> workers = ExpectWorkersInTheirOwnGroups(command);
  const std::string partial = Out("cut") + "/results.jsonl.partial";
  ASSERT_TRUE(AwaitWhileRunning(command, [&] { return Lines(ReadIfThere(partial)).size() >= 2; }))
      << "2 of 10 results before the end: " << command.err();

  const Clock::time_point signalled = Clock::now();
  command.SignalGroup(SIGINT);
  const std::optional<ProcessResult> ended = command.Wait(milliseconds(5000));
  ASSERT_TRUE(ended.has_value()) << "still running 5 s after Ctrl-C";
  const double seconds = SecondsSince(signalled);
  std::cout << "[ measured ] run: exit " << seconds << " s after one Ctrl-C\n";
  EXPECT_LT(seconds, 5.0);
  EXPECT_EQ(ended->exit_code, kExitInterrupted) << ended->out << ended->err;
  const std::string resume = "orcs-batch run --resume " + Out("cut") + " --workers 2";
  EXPECT_THAT(ended->err, HasSubstr("continue with: " + resume));
  EXPECT_EQ(Progress(Out("cut")).value_or(nlohmann::json())["state"], "interrupted");
  ExpectNoneLeft(workers);
  const std::vector<std::string> before = Lines(ReadIfThere(partial));
  ASSERT_LT(before.size(), 10u) << "the batch ended before the interruption took";

  // The command it printed (orcs-batch is this build's).
  const ProcessResult resumed = RunProcess({kBatch, "run", "--resume", Out("cut"), "--workers", "2"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const std::vector<std::string> after = Lines(ReadIfThere(Out("cut") + "/results.jsonl"));
  ASSERT_EQ(after.size(), 10u) << "one line per job";
  EXPECT_EQ(ByJob(after), ByJob(Lines(ReadIfThere(Out("whole") + "/results.jsonl"))));
  EXPECT_EQ(Progress(Out("cut")).value_or(nlohmann::json())["state"], "finished");
}

TEST_F(CtrlCTest, EvolveStopsOnOneCtrlCToItsGroupWithinFiveSecondsAndItsResumeCommandGivesTheUninterruptedBits) {
  const std::string scenario = dir_.Write("s.json", Scenario(0.2));
  const std::vector<std::string> evolve = {kBatch, "evolve", scenario, "--workers", "2", "--no-plot", "--quiet"};
  std::vector<std::string> whole = evolve;
  whole.insert(whole.end(), {"--out", Out("whole")});
  const ProcessResult uninterrupted = RunProcess(whole);
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;

  std::vector<std::string> cut = evolve;
  cut.insert(cut.end(), {"--out", Out("cut")});
  BackgroundProcess command(cut, /*own_process_group=*/true);
  const std::vector<ProcInfo> workers = ExpectWorkersInTheirOwnGroups(command);
  // Generation 1 under way: its start is in progress.json (written at once when a generation begins).
  ASSERT_TRUE(AwaitWhileRunning(command, [&] {
    const std::optional<nlohmann::json> progress = Progress(Out("cut"));
    return progress && progress->value("generation", 0) >= 1;
  })) << command.err();

  const Clock::time_point signalled = Clock::now();
  command.SignalGroup(SIGINT);
  const std::optional<ProcessResult> ended = command.Wait(milliseconds(5000));
  ASSERT_TRUE(ended.has_value()) << "still running 5 s after Ctrl-C (issue 47: it never ended)";
  const double seconds = SecondsSince(signalled);
  std::cout << "[ measured ] evolve: exit " << seconds << " s after one Ctrl-C\n";
  EXPECT_LT(seconds, 5.0);
  EXPECT_EQ(ended->exit_code, kExitInterrupted) << ended->out << ended->err;
  EXPECT_THAT(ended->err, HasSubstr("interrupted (Ctrl-C or SIGTERM) after generation"));
  EXPECT_THAT(ended->err, HasSubstr("continue with: orcs-batch evolve --resume " + Out("cut") + " --workers 2\n"));
  EXPECT_EQ(Progress(Out("cut")).value_or(nlohmann::json())["state"], "interrupted");
  ExpectNoneLeft(workers);
  const std::size_t done = Lines(ReadIfThere(Out("cut") + "/fitness.csv")).size();
  ASSERT_LT(done, 4u) << "a header and generations 0 to 2: the run ended before the interruption took";

  const ProcessResult resumed = RunProcess({kBatch, "evolve", "--resume", Out("cut"), "--workers", "2", "--no-plot"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  EXPECT_EQ(WithoutSeconds(ReadIfThere(Out("cut") + "/fitness.csv")),
            WithoutSeconds(ReadIfThere(Out("whole") + "/fitness.csv")));
  EXPECT_EQ(ReadIfThere(Out("cut") + "/best_genome.json"), ReadIfThere(Out("whole") + "/best_genome.json"));
  EXPECT_EQ(Progress(Out("cut")).value_or(nlohmann::json())["state"], "finished");
}

// The first Ctrl-C's orderly stop is short (the broker revokes the jobs, the workers stop them at once), too short
// to be sure of a second Ctrl-C inside it. What makes a second one needed is a worker that does not answer: one
// worker, with its simulation process, is stopped (SIGSTOP, as a wedged or swapped-out process), so the orderly stop
// waits for it for its grace of a second — and the second Ctrl-C must end everything at once, that worker too.
TEST_F(CtrlCTest, ASecondCtrlCExitsWithinOneSecondKillsTheWorkersAndLeavesAResumableFolder) {
  const std::string scenario = dir_.Write("s.json", Scenario(1.0));
  const std::vector<std::string> batch = {kBatch, "run", scenario, "--jobs", "4", "--workers", "2", "--quiet"};
  std::vector<std::string> cut = batch;
  cut.insert(cut.end(), {"--out", Out("cut")});
  BackgroundProcess command(cut, /*own_process_group=*/true);
  const std::vector<ProcInfo> workers = ExpectWorkersInTheirOwnGroups(command);
  ASSERT_FALSE(workers.empty());
  const std::string partial = Out("cut") + "/results.jsonl.partial";
  ASSERT_TRUE(AwaitWhileRunning(command, [&] { return !Lines(ReadIfThere(partial)).empty(); })) << command.err();

  const ProcInfo stopped = workers.front();  // a worker (its simulation process is in its group)
  const KilledAtTheEnd unless_gone(stopped);  // a failed assertion below must not leave it stopped for ever
  ASSERT_EQ(::kill(-stopped.pgrp, SIGSTOP), 0) << "worker " << stopped.pid;
  command.SignalGroup(SIGINT);
  const std::optional<ProcessResult> early = command.Wait(milliseconds(50));  // waiting for the stopped worker
  ASSERT_FALSE(early.has_value()) << "ended before the second Ctrl-C, with a worker stopped: " << early->err;
  const Clock::time_point second = Clock::now();
  command.SignalGroup(SIGINT);
  const std::optional<ProcessResult> ended = command.Wait(milliseconds(1000));
  ASSERT_TRUE(ended.has_value()) << "still running 1 s after the second Ctrl-C";
  const double seconds = SecondsSince(second);
  std::cout << "[ measured ] run: exit " << seconds << " s after a second Ctrl-C\n";
  EXPECT_LT(seconds, 1.0);
  EXPECT_EQ(ended->exit_code, kExitInterrupted) << ended->out << ended->err;
  // The second Ctrl-C's own line, not the orderly stop's (which would also end within about a second, its grace).
  EXPECT_THAT(ended->err, HasSubstr("stopped at once (a second Ctrl-C)"));
  EXPECT_THAT(ended->err, HasSubstr("continue with: orcs-batch run --resume " + Out("cut") + " --workers 2"));
  ExpectNoneLeft(workers);

  const ProcessResult resumed = RunProcess({kBatch, "run", "--resume", Out("cut"), "--workers", "2", "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  std::vector<std::string> whole = batch;
  whole.insert(whole.end(), {"--out", Out("whole")});
  const ProcessResult uninterrupted = RunProcess(whole);
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;
  const std::vector<std::string> after = Lines(ReadIfThere(Out("cut") + "/results.jsonl"));
  ASSERT_EQ(after.size(), 4u) << "one line per job";
  EXPECT_EQ(ByJob(after), ByJob(Lines(ReadIfThere(Out("whole") + "/results.jsonl"))));
}

// orcs-gap has no resume: one Ctrl-C abandons the diagnosis (every fit's wait stops), says so and to run it again,
// and exits 130 within 5 s with nothing left running.
TEST_F(CtrlCTest, GapAbandonsItsDiagnosisOnOneCtrlCSaysItHasNoResumeAndExitsWithinFiveSeconds) {
  const std::string data = Out("data");
  const ProcessResult made = RunProcess({kGap, "synth", "--rig", "pendulum", "--motion",
                                         kMotions + "pendulum_identification_a.csv",
                                         kMotions + "pendulum_identification_b.csv", "--duration", "2", "--out", data});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  BackgroundProcess command({kGap, "--rig", "pendulum", "--measured", data + "/pendulum_identification_a.csv",
                             "--holdout", data + "/pendulum_identification_b.csv", "--workers", "2",
                             "--generations", "40", "--out", Out("report")},
                            /*own_process_group=*/true);
  const std::vector<ProcInfo> workers = ExpectWorkersInTheirOwnGroups(command);
  ASSERT_TRUE(AwaitWhileRunning(command, [&] { return command.err().find("orcs-gap: fitting") != std::string::npos; }))
      << command.err();

  const Clock::time_point signalled = Clock::now();
  command.SignalGroup(SIGINT);
  const std::optional<ProcessResult> ended = command.Wait(milliseconds(5000));
  ASSERT_TRUE(ended.has_value()) << "still running 5 s after Ctrl-C";
  const double seconds = SecondsSince(signalled);
  std::cout << "[ measured ] orcs-gap: exit " << seconds << " s after one Ctrl-C\n";
  EXPECT_LT(seconds, 5.0);
  EXPECT_EQ(ended->exit_code, kExitInterrupted) << ended->err;
  EXPECT_THAT(ended->err, HasSubstr("orcs-gap has no resume: run the same command again"));
  EXPECT_EQ(Progress(Out("report")).value_or(nlohmann::json())["state"], "interrupted");
  EXPECT_FALSE(fs::exists(Out("report") + "/report.md"));
  ExpectNoneLeft(workers);
}

}  // namespace
}  // namespace orcs
