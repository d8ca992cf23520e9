#include "worker/job/simulation_sandbox.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <utility>

#include "model/core/text.h"
#include "worker/job/frame_channel.h"
#include "worker/job/sandbox_child.h"

extern char** environ;

namespace orcs::worker {
namespace {

using Clock = std::chrono::steady_clock;

// Time limits beyond this many seconds (115 days) get no watchdog: their deadline would overflow the clock.
constexpr double kLongestWatchedLimit = 1e7;
// A process that closed its channel is dying; if it has not ended after this long, it is killed.
constexpr std::chrono::milliseconds kReapPatience{2000};
// Signals the simulation process starts with at their default action whatever the worker did with them.
constexpr int kDefaultSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE, SIGCHLD, SIGHUP, SIGXCPU};

Clock::duration ToDuration(double seconds) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A result the simulation process did not write: the job's ids, a status and why.
v1::Result Failed(const v1::Job& job, v1::Result::Status status, const std::string& message, Clock::time_point start) {
  v1::Result result;
  result.set_job_id(job.job_id());
  result.set_batch_id(job.batch_id());
  result.set_status(status);
  result.set_message(message);
  result.mutable_timings()->set_run_seconds(SecondsSince(start));
  result.set_attempts(job.attempt() + 1);
  return result;
}

// "the simulation process died of SIGSEGV (Segmentation fault)" for a wait status.
std::string DescribeDeath(int status) {
  if (WIFSIGNALED(status)) return "the simulation process died of " + SignalName(WTERMSIG(status));
  if (WIFEXITED(status)) {
    return "the simulation process exited with code " + std::to_string(WEXITSTATUS(status)) + " while running the job";
  }
  return "the simulation process ended while running the job (wait status " + std::to_string(status) + ")";
}

// posix_spawn's attributes and descriptor moves, freed on every path.
class SpawnSetup {
 public:
  explicit SpawnSetup(int channel_fd) {
    posix_spawn_file_actions_init(&actions_);
    posix_spawnattr_init(&attributes_);
    posix_spawn_file_actions_adddup2(&actions_, channel_fd, kSandboxChannelFd);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attributes_, &none);  // the worker's threads may block signals
    sigset_t defaults;
    sigemptyset(&defaults);
    for (int signal : kDefaultSignals) sigaddset(&defaults, signal);
    posix_spawnattr_setsigdefault(&attributes_, &defaults);
    // Its own process group: a terminal's Ctrl-C goes to the worker, which finishes the job and stops.
    posix_spawnattr_setpgroup(&attributes_, 0);
    posix_spawnattr_setflags(&attributes_, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions_);
    posix_spawnattr_destroy(&attributes_);
  }
  SpawnSetup(const SpawnSetup&) = delete;
  SpawnSetup& operator=(const SpawnSetup&) = delete;
  const posix_spawn_file_actions_t* actions() const { return &actions_; }
  const posix_spawnattr_t* attributes() const { return &attributes_; }

 private:
  posix_spawn_file_actions_t actions_;
  posix_spawnattr_t attributes_;
};

// A job's result when its process died: TIMEOUT when it spent its CPU time (SIGXCPU), CRASHED otherwise.
v1::Result DiedWhileRunning(const v1::Job& job, int status, Clock::time_point start) {
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU) {
    return Failed(job, v1::Result::TIMEOUT,
                  "time limit of " + text::FormatDouble(job.time_limit_seconds()) +
                      " s exceeded: the simulation process used up its " +
                      std::to_string(CpuSecondsFor(job.time_limit_seconds())) +
                      " s of CPU time (RLIMIT_CPU: the limit, its grace and 1 s) and was killed by SIGXCPU",
                  start);
  }
  return Failed(job, v1::Result::CRASHED, DescribeDeath(status), start);
}

}  // namespace

std::uint64_t CpuSecondsFor(double time_limit_seconds) {
  if (!(time_limit_seconds > 0 && time_limit_seconds <= kLongestWatchedLimit)) return 0;
  const double grace = std::chrono::duration<double>(SimulationSandbox::Grace(time_limit_seconds)).count();
  return static_cast<std::uint64_t>(std::ceil(time_limit_seconds + grace)) + 1;
}

std::string SignalName(int signal) {
  const char* abbreviation = ::sigabbrev_np(signal);
  if (abbreviation == nullptr) return "signal " + std::to_string(signal);
  return std::string("SIG") + abbreviation + " (" + ::strsignal(signal) + ")";
}

SimulationSandbox::SimulationSandbox(std::vector<std::string> child_argv, SandboxLimits limits)
    : child_argv_(std::move(child_argv)), limits_(limits) {
  if (child_argv_.empty()) throw std::invalid_argument("SimulationSandbox: no program to start");
  Start();
}

SimulationSandbox::~SimulationSandbox() {
  if (pid_ > 0) Stop();
  CloseChannel();
}

Clock::duration SimulationSandbox::Grace(double time_limit_seconds) {
  return ToDuration(1.0 + 0.25 * time_limit_seconds);
}

v1::Result SimulationSandbox::Run(const v1::Job& job, const RunStop& stop) {
  const Clock::time_point start = Clock::now();
  out_.clear();
  job.SerializeToString(&out_);
  // A process that died while idle (killed from outside) is not this job's doing: up to two fresh starts.
  for (int tries = 0; !Idle() || !FrameChannel(fd_).Write(out_); ++tries) {
    if (pid_ > 0) Stop();
    if (tries == 2) {
      return Failed(job, v1::Result::INTERNAL_ERROR, "cannot hand the job to a simulation process", start);
    }
    try {
      Start();
    } catch (const std::exception& error) {
      return Failed(job, v1::Result::INTERNAL_ERROR, error.what(), start);
    }
  }
  const double limit = job.time_limit_seconds();
  const Clock::time_point deadline = limit > 0 && limit <= kLongestWatchedLimit
                                         ? start + ToDuration(limit) + SimulationSandbox::Grace(limit)
                                         : Clock::time_point::max();
  if (StoppedBeforeAnswer(stop, deadline)) {
    Stop();
    return Failed(job, v1::Result::INTERNAL_ERROR, "stopped: the broker revoked the job", start);
  }
  v1::Result result;
  switch (FrameChannel(fd_).Read(in_, deadline)) {
    case FrameChannel::ReadStatus::kOk:
      if (result.ParseFromString(in_)) return result;
      Stop();
      return Failed(job, v1::Result::INTERNAL_ERROR, "the simulation process sent a result that does not parse", start);
    case FrameChannel::ReadStatus::kTimedOut:
      Stop();
      return Failed(job, v1::Result::TIMEOUT,
                    "time limit of " + text::FormatDouble(limit) +
                        " s exceeded: the simulation process did not answer within " +
                        text::FormatDouble(std::chrono::duration<double>(deadline - start).count()) +
                        " s and was killed",
                    start);
    case FrameChannel::ReadStatus::kClosed:
    case FrameChannel::ReadStatus::kBroken:
      break;
  }
  return DiedWhileRunning(job, Reap(), start);
}

bool SimulationSandbox::StoppedBeforeAnswer(const RunStop& stop, Clock::time_point deadline) {
  if (stop.fd < 0) return false;
  while (true) {
    pollfd items[2] = {{fd_, POLLIN, 0}, {stop.fd, POLLIN, 0}};
    int timeout = -1;
    if (deadline != Clock::time_point::max()) {
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
      timeout = static_cast<int>(std::clamp<long long>(left, 0, 1 << 30));
    }
    const int ready = ::poll(items, 2, timeout);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0 || items[0].revents != 0) return false;  // the answer (or the deadline) is for Read to see
    if (stop.stop && stop.stop()) return true;
    return false;  // readable for another job's sake: wait for this one's answer as usual
  }
}

bool SimulationSandbox::Idle() const {
  if (pid_ < 0) return false;
  // Between jobs the process sends nothing: a hang-up, an error or unasked-for bytes mean it is dead or confused.
  pollfd item{fd_, POLLIN | POLLRDHUP, 0};
  return ::poll(&item, 1, 0) == 0;
}

void SimulationSandbox::Start() {
  CloseChannel();
  int ends[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) {
    throw std::runtime_error(std::string("cannot start the simulation process: socketpair: ") + std::strerror(errno));
  }
  fd_ = ends[0];
  int child_end = ends[1];
  int error = 0;
  if (child_end == kSandboxChannelFd) {  // dup2 onto itself would keep close-on-exec: move it out of the way
    child_end = ::fcntl(ends[1], F_DUPFD_CLOEXEC, kSandboxChannelFd + 1);
    error = child_end < 0 ? errno : 0;
    ::close(ends[1]);
  }
  std::vector<char*> argv;
  for (const std::string& argument : child_argv_) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  if (child_end >= 0) {
    const SpawnSetup setup(child_end);
    error = ::posix_spawn(&pid_, argv[0], setup.actions(), setup.attributes(), argv.data(), environ);
  }
  if (child_end >= 0) ::close(child_end);
  if (error != 0) {
    pid_ = -1;
    CloseChannel();
    throw std::runtime_error("cannot start the simulation process '" + child_argv_[0] + "': " + std::strerror(error));
  }
  ++processes_started_;
  LimitMemory();
}

void SimulationSandbox::LimitMemory() {
  if (limits_.memory_bytes == 0) return;
  // Set from here, before the first job goes down the channel: the process itself needs no arguments for it.
  const rlimit memory{limits_.memory_bytes, limits_.memory_bytes};
  if (::prlimit(pid_, RLIMIT_AS, &memory, nullptr) != 0) {
    const int error = errno;
    Stop();
    throw std::runtime_error("cannot limit the simulation process's memory to " +
                             std::to_string(limits_.memory_bytes >> 20) + " MiB: prlimit: " + std::strerror(error));
  }
}

int SimulationSandbox::Stop() {
  if (pid_ <= 0) return 0;  // kill(-1) would reach every process we may signal
  ::kill(pid_, SIGKILL);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  CloseChannel();
  return status;
}

int SimulationSandbox::Reap() {
  // Its channel closes as it exits, so it is (nearly) gone: wait a little for its own status before killing it.
  const Clock::time_point give_up = Clock::now() + kReapPatience;
  int status = 0;
  while (Clock::now() < give_up) {
    const pid_t done = ::waitpid(pid_, &status, WNOHANG);
    if (done == pid_ || (done < 0 && errno != EINTR)) {
      pid_ = -1;
      CloseChannel();
      return status;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return Stop();
}

void SimulationSandbox::CloseChannel() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace orcs::worker
