// SimulationSandbox with the real simulation process (orcs-worker --sandbox-child): a job gives the same bits as
// in-process, a crash costs one job and the next job runs in a fresh process, time limits hold — the simulation's
// own and, for a hang inside the engine, the sandbox's.
#include "worker/job/simulation_sandbox.h"

#include <gmock/gmock.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <thread>

#include "model/evaluation/recording_reader.h"
#include "tests/support/process.h"
#include "worker/job/frame_channel.h"
#include "worker/job/job_translation.h"

extern char** environ;

namespace orcs::worker {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kWorker = ORCS_BINARY_DIR "/bin/orcs-worker";

// One A-Series swinging its hips for `duration` simulated seconds under two parameter sets; `fault` when not null.
v1::Job Job(const std::string& id, double duration, const nlohmann::json& fault = nullptr) {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]},
    "randomisation": {"sets": 2, "default_motor_model": true}})");
  scenario["duration"] = duration;
  if (!fault.is_null()) scenario["fault"] = fault;
  v1::Job job;
  job.set_job_id(id);
  job.set_batch_id("sandbox-test");
  job.set_scenario_json(scenario.dump());
  job.set_genome_json("[20, 1.5, 0, 0, 20, 1.5, 3, 0]");
  job.set_seed(77);
  job.set_time_limit_seconds(60);
  return job;
}

std::vector<std::string> ChildArguments() { return {kWorker, "--sandbox-child"}; }

// Equal as results, bit for bit, apart from the wall-clock time each took.
void ExpectSameBits(v1::Result a, v1::Result b) {
  a.mutable_timings()->clear_run_seconds();
  b.mutable_timings()->clear_run_seconds();
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(a, b))  // doubles compared exactly
      << a.DebugString() << "\nvs\n"
      << b.DebugString();
}

bool Running(pid_t pid) { return pid > 0 && ::kill(pid, 0) == 0; }

// Whether `pid` has died and waits to be reaped (state Z in /proc/PID/stat), without reaping it.
bool Zombie(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t name_end = text.rfind(')');
  return name_end != std::string::npos && name_end + 2 < text.size() && text[name_end + 2] == 'Z';
}

// Waits (bounded: 10 s unless told) for `condition`.
bool AwaitTrue(const std::function<bool()>& condition,
               std::chrono::steady_clock::duration patience = std::chrono::seconds(10)) {
  const auto give_up = std::chrono::steady_clock::now() + patience;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a poll: the awaited processes need the cores
  }
  return true;
}

TEST(SimulationSandbox, AJobGivesTheSameBitsAsInProcess) {
  SimulationSandbox sandbox(ChildArguments());
  const v1::Job job = Job("same", 0.3);
  const v1::Result in_process = RunJob(job);
  ASSERT_EQ(in_process.status(), v1::Result::OK) << in_process.message();
  const v1::Result sandboxed = sandbox.Run(job);
  ASSERT_EQ(sandboxed.status(), v1::Result::OK) << sandboxed.message();
  ExpectSameBits(sandboxed, in_process);
  ExpectSameBits(sandbox.Run(job), in_process);  // and again in the same process: nothing carries over
  EXPECT_EQ(sandbox.processes_started(), 1);
}

TEST(SimulationSandbox, ARecordingComesBackThroughTheChannelAndChangesNoBits) {
  SimulationSandbox sandbox(ChildArguments());
  const v1::Job plain = Job("plain", 0.3);
  v1::Job recorded = plain;
  recorded.set_record(true);
  recorded.set_record_set(1);
  const v1::Result with = sandbox.Run(recorded);
  ASSERT_EQ(with.status(), v1::Result::OK) << with.message();
  const evaluation::Recording recording = evaluation::ParseRecording(with.recording(), "result");
  EXPECT_EQ(recording.frame_count(), 31);  // frame 0 and 30 steps of 10 ms
  EXPECT_EQ(recording.header["source"]["set"], 1);
  EXPECT_EQ(recording.header["program"], "orcs-worker");
  v1::Result without_recording = with;
  without_recording.clear_recording();
  ExpectSameBits(without_recording, RunJob(plain));  // the numbers: the same bits as unrecorded

  recorded.set_record_set(2);  // the job has sets 0 and 1
  const v1::Result bad = sandbox.Run(recorded);
  EXPECT_EQ(bad.status(), v1::Result::INVALID_INPUT);
  EXPECT_EQ(bad.message(), "job plain record_set: expected a parameter set of the job, 0…1, found 2");
  EXPECT_TRUE(bad.recording().empty());
}

TEST(SimulationSandbox, ASegfaultCostsOneJobAndTheNextRunsInAFreshProcess) {
  SimulationSandbox sandbox(ChildArguments());
  const pid_t first = sandbox.child_pid();
  ASSERT_TRUE(Running(first));
  const v1::Result crashed = sandbox.Run(Job("segv", 0.3, {{"kind", "segfault"}, {"at_step", 10}}));
  EXPECT_EQ(crashed.status(), v1::Result::CRASHED);
  EXPECT_EQ(crashed.message(), "the simulation process died of SIGSEGV (Segmentation fault)");
  EXPECT_EQ(crashed.job_id(), "segv");
  EXPECT_EQ(crashed.batch_id(), "sandbox-test");
  EXPECT_EQ(crashed.attempts(), 1u);
  EXPECT_EQ(sandbox.child_pid(), -1) << "the dead process was reaped";

  const v1::Job next = Job("next", 0.3);
  const v1::Result result = sandbox.Run(next);
  EXPECT_EQ(result.status(), v1::Result::OK) << result.message();
  ExpectSameBits(result, RunJob(next));
  EXPECT_EQ(sandbox.processes_started(), 2);
  EXPECT_NE(sandbox.child_pid(), first);
}

TEST(SimulationSandbox, AnAbortIsReportedWithItsSignal) {
  SimulationSandbox sandbox(ChildArguments());
  const v1::Result crashed = sandbox.Run(Job("abort", 0.3, {{"kind", "abort"}, {"at_step", 0}}));
  EXPECT_EQ(crashed.status(), v1::Result::CRASHED);
  EXPECT_EQ(crashed.message(), "the simulation process died of SIGABRT (Aborted)");
  EXPECT_EQ(sandbox.Run(Job("after", 0.1)).status(), v1::Result::OK);
}

TEST(SimulationSandbox, AFaultIsIgnoredOutsideTheSandbox) {
  const v1::Result result = RunJob(Job("in-process", 0.1, {{"kind", "segfault"}, {"at_step", 3}}));
  EXPECT_EQ(result.status(), v1::Result::OK) << "this test process is still alive";
}

TEST(SimulationSandbox, TheSimulationsOwnTimeLimitStillGivesTimeout) {
  SimulationSandbox sandbox(ChildArguments());
  v1::Job job = Job("long", 1000.0);  // far more than a 0.3 s limit allows
  job.set_time_limit_seconds(0.3);
  const v1::Result result = sandbox.Run(job);
  EXPECT_EQ(result.status(), v1::Result::TIMEOUT);
  EXPECT_THAT(result.message(), StartsWith("time limit of 0.3 s exceeded in parameter set 0"));
  EXPECT_EQ(sandbox.processes_started(), 1) << "a timeout is a result, not a death";
  EXPECT_TRUE(Running(sandbox.child_pid()));
}

TEST(SimulationSandbox, AHangInsideTheEngineIsKilledAfterTheLimitAndItsGrace) {
  SimulationSandbox sandbox(ChildArguments());
  v1::Job job = Job("hang", 1.0, {{"kind", "hang"}, {"at_step", 5}});
  job.set_time_limit_seconds(0.2);
  const pid_t hung = sandbox.child_pid();
  const auto start = std::chrono::steady_clock::now();
  const v1::Result result = sandbox.Run(job);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(result.status(), v1::Result::TIMEOUT);
  EXPECT_EQ(result.message(),
            "time limit of 0.2 s exceeded: the simulation process did not answer within 1.25 s and was killed");
  EXPECT_GE(waited, 1.25);  // the grace: 1 s + 25 % of the limit
  EXPECT_FALSE(Running(hung)) << "killed and reaped";
  EXPECT_EQ(sandbox.Run(Job("after", 0.1)).status(), v1::Result::OK);
  EXPECT_EQ(sandbox.processes_started(), 2);
}

TEST(SimulationSandbox, AProcessKilledWhileIdleCostsNoJob) {
  SimulationSandbox sandbox(ChildArguments());
  const pid_t idle = sandbox.child_pid();
  ASSERT_EQ(::kill(idle, SIGKILL), 0);
  ASSERT_TRUE(AwaitTrue([&] { return Zombie(idle); }));  // dead before the job is handed over
  const v1::Result result = sandbox.Run(Job("unlucky", 0.1));
  EXPECT_EQ(result.status(), v1::Result::OK) << result.message();
  EXPECT_EQ(sandbox.processes_started(), 2);
}

TEST(SimulationSandbox, TheProcessEndsWithTheSandbox) {
  pid_t pid = -1;
  {
    SimulationSandbox sandbox(ChildArguments());
    pid = sandbox.child_pid();
    ASSERT_TRUE(Running(pid));
  }
  EXPECT_FALSE(Running(pid)) << "killed and reaped, no zombie left";
}

TEST(SimulationSandbox, AnExitWhileRunningAJobIsCrashedWithItsCode) {
  // A stand-in simulation process that reads the start of the job, then exits with code 4.
  SimulationSandbox sandbox({"/bin/sh", "-c", "head -c 4 <&3 >/dev/null; exit 4"});
  const v1::Result result = sandbox.Run(Job("quitter", 0.1));
  EXPECT_EQ(result.status(), v1::Result::CRASHED);
  EXPECT_EQ(result.message(), "the simulation process exited with code 4 while running the job");
}

// ---- resource limits ----

// The process's address space now, bytes (VmSize in /proc/PID/status).
std::uint64_t AddressSpace(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) << 10;  // kB
  }
  return 0;
}

TEST(SimulationSandbox, AJobPastTheMemoryLimitIsCrashedNamingTheLimitAndTheNextJobRuns) {
  std::uint64_t warm = 0;  // what a simulation process takes once it has run a job
  {
    SimulationSandbox measure(ChildArguments());
    ASSERT_EQ(measure.Run(Job("warm-up", 0.1)).status(), v1::Result::OK);
    warm = AddressSpace(measure.child_pid());
    ASSERT_GT(warm, 0u);
  }
  const std::uint64_t limit = warm + (std::uint64_t{48} << 20);
  SimulationSandbox sandbox(ChildArguments(), SandboxLimits{.memory_bytes = limit});
  v1::Job greedy = Job("greedy", 1000.0);  // logging every value for 1000 s: far more than 48 MiB
  nlohmann::json scenario = nlohmann::json::parse(greedy.scenario_json());
  scenario["log"] = {".*"};
  greedy.set_scenario_json(scenario.dump());
  const v1::Result result = sandbox.Run(greedy);
  EXPECT_EQ(result.status(), v1::Result::CRASHED);
  EXPECT_EQ(result.message(), "out of memory: the simulation process may use at most " + std::to_string(limit >> 20) +
                                  " MiB (orcs-worker --memory-limit); log fewer values, record less or raise the limit");
  const v1::Result after = sandbox.Run(Job("after", 0.1));
  EXPECT_EQ(after.status(), v1::Result::OK) << after.message();
  EXPECT_EQ(sandbox.processes_started(), 1) << "the allocation failed, the process lived on";
}

TEST(SimulationSandbox, AProcessKilledForItsCpuTimeIsTimeoutNamingTheLimit) {
  // A stand-in simulation process that reads the start of the job, then gets what RLIMIT_CPU sends.
  SimulationSandbox sandbox({"/bin/sh", "-c", "head -c 4 <&3 >/dev/null; kill -XCPU $$"});
  const v1::Result result = sandbox.Run(Job("spender", 0.1));  // time limit 60 s: 60 + 16 s grace + 1 s
  EXPECT_EQ(result.status(), v1::Result::TIMEOUT);
  EXPECT_EQ(result.message(),
            "time limit of 60 s exceeded: the simulation process used up its 77 s of CPU time (RLIMIT_CPU: the "
            "limit, its grace and 1 s) and was killed by SIGXCPU");
}

// The simulation process bounds its own CPU time per job, even when no worker watches the clock (here: nobody reads
// its channel; in life, a worker stopped with SIGSTOP).
TEST(SimulationSandbox, TheSimulationProcessBoundsItsOwnCpuTimeToTheJobsLimit) {
  int ends[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends), 0);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, ends[1], 3);
  const char* argv[] = {kWorker.c_str(), "--sandbox-child", nullptr};
  pid_t pid = -1;
  ASSERT_EQ(::posix_spawn(&pid, argv[0], &actions, nullptr, const_cast<char**>(argv), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  ::close(ends[1]);

  v1::Job spinner = Job("spinner", 1.0, {{"kind", "spin"}, {"at_step", 1}});
  spinner.set_time_limit_seconds(0.1);  // CPU: 0.1 s + 1.025 s grace, rounded up, + 1 s = 3 s
  ASSERT_EQ(CpuSecondsFor(0.1), 3u);
  std::string bytes;
  spinner.SerializeToString(&bytes);
  ASSERT_TRUE(FrameChannel(ends[0]).Write(bytes));

  int status = 0;
  rusage usage = {};
  ASSERT_TRUE(AwaitTrue([&] { return ::wait4(pid, &status, WNOHANG, &usage) == pid; }, std::chrono::seconds(30)));
  ::close(ends[0]);
  ASSERT_TRUE(WIFSIGNALED(status)) << "wait status " << status;
  EXPECT_EQ(WTERMSIG(status), SIGXCPU);
  const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                     1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  // The process's whole CPU time: what it used before the job (under 1 s, counted as 1 s) and the job's 3 s; the
  // kernel checks the limit on its timer ticks, late by up to a second here when the machine is loaded.
  EXPECT_GE(cpu, 3.0);
  EXPECT_LE(cpu, 6.0);
}

TEST(SimulationSandbox, TheHiddenModeTypedByHandSaysWhatItIsFor) {
  const test_support::ProcessResult run = test_support::RunProcess({kWorker, "--sandbox-child"});
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_EQ(run.err,
            "orcs-worker: --sandbox-child is started by orcs-worker itself, with its job channel on descriptor 3, "
            "which is not a socket here\n");
}

TEST(SimulationSandbox, AProgramThatCannotStartIsNamed) {
  try {
    SimulationSandbox sandbox({"/nonexistent/orcs-worker", "--sandbox-child"});
    FAIL() << "expected a failure to start";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot start the simulation process '/nonexistent/orcs-worker'"));
  }
}

TEST(SimulationSandbox, GraceGrowsWithTheLimit) {
  using std::chrono::duration;
  EXPECT_DOUBLE_EQ(duration<double>(SimulationSandbox::Grace(0.0)).count(), 1.0);
  EXPECT_DOUBLE_EQ(duration<double>(SimulationSandbox::Grace(60.0)).count(), 16.0);
}

// Issue 47: a job the broker revoked stops at once — the simulation process is killed — and the next job runs in a
// fresh one; a stop signal meant for another job (stop() false) changes nothing.
TEST(SimulationSandbox, ARevokedJobStopsAtOnceAndTheNextRunsInAFreshProcess) {
  SimulationSandbox sandbox(ChildArguments());
  const int signal = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  ASSERT_GE(signal, 0);
  // Revoked as it is handed over: a job of 600 simulated seconds that returns at all was stopped.
  const pid_t running = sandbox.child_pid();
  const std::uint64_t signalled = 1;
  ASSERT_EQ(::write(signal, &signalled, sizeof signalled), static_cast<ssize_t>(sizeof signalled));
  const v1::Result result = sandbox.Run(Job("long", 600.0), RunStop{signal, [] { return true; }});
  EXPECT_EQ(result.status(), v1::Result::INTERNAL_ERROR);
  EXPECT_THAT(result.message(), HasSubstr("revoked"));
  EXPECT_FALSE(Running(running)) << "killed and reaped";
  std::uint64_t drained = 0;
  ASSERT_EQ(::read(signal, &drained, sizeof drained), static_cast<ssize_t>(sizeof drained));

  // A readable signal whose stop() says "not this job" lets the job finish as usual.
  const std::uint64_t one = 1;
  ASSERT_EQ(::write(signal, &one, sizeof one), static_cast<ssize_t>(sizeof one));
  const v1::Result after = sandbox.Run(Job("after", 0.1), RunStop{signal, [] { return false; }});
  EXPECT_EQ(after.status(), v1::Result::OK) << after.message();
  EXPECT_EQ(sandbox.processes_started(), 2);
  ::close(signal);
}

}  // namespace
}  // namespace orcs::worker
