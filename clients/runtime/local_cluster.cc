#include "clients/runtime/local_cluster.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "clients/runtime/interrupt.h"
#include "net/curve_keys.h"

namespace orcs::runtime {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// How long stopped workers get to finish the job in hand before SIGKILL; after Ctrl-C less (the client will not
// wait for those results, and the command must end within 5 s).
constexpr std::chrono::milliseconds kStopGrace{3000};
constexpr std::chrono::milliseconds kInterruptedStopGrace{1000};

std::string SecondsText(std::chrono::milliseconds interval) {
  return std::to_string(static_cast<double>(interval.count()) / 1000.0);
}

}  // namespace

std::string WorkerProgramBesideSelf() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) return "";
  const fs::path worker = self.parent_path() / "orcs-worker";
  return fs::exists(worker, error) ? worker.string() : "";
}

LocalCluster::LocalCluster(LocalClusterOptions options) : options_(std::move(options)) {
  if (options_.workers < 1) throw std::invalid_argument("LocalCluster: at least one worker");
  if (options_.worker_program.empty() || access(options_.worker_program.c_str(), X_OK) != 0) {
    throw std::runtime_error("cannot run the worker program '" + options_.worker_program +
                             "' (orcs-worker belongs next to orcs-batch)");
  }
  const std::string log_path = options_.log_path.empty() ? "/dev/null" : options_.log_path;
  log_fd_ = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd_ < 0) throw std::runtime_error("cannot open the log file " + log_path + ": " + std::strerror(errno));

  // The workers' keys checked here, so that a bad one is this program's error rather than workers that exit.
  if (!options_.curve_keys.empty()) net::LoadCurvePeerKeys(options_.curve_keys, "worker");
  broker::BrokerOptions broker_options;  // loopback, ephemeral ports
  broker_options.heartbeat_interval = options_.heartbeat_interval;
  broker_options.curve_keys = options_.curve_keys;
  broker_options.log = [this](std::string_view line) {
    const std::string text = "orcs-broker: " + std::string(line) + "\n";
    std::lock_guard lock(log_mutex_);
    [[maybe_unused]] const ssize_t written = write(log_fd_, text.data(), text.size());
  };
  broker_ = std::make_unique<broker::Broker>(broker_options);
  broker_thread_ = std::thread([this] { broker_->Run(); });
  try {
    for (int i = 0; i < options_.workers; ++i) workers_.push_back(StartWorker(i));
  } catch (...) {
    StopWorkers();
    broker_->Stop();
    broker_thread_.join();
    close(log_fd_);
    throw;
  }
}

LocalCluster::~LocalCluster() {
  StopWorkers();
  broker_->Stop();
  broker_thread_.join();
  close(log_fd_);
}

pid_t LocalCluster::StartWorker(int index) const {
  std::vector<std::string> arguments = {
      options_.worker_program, "--connect", broker_->worker_endpoint(), "--id", "local-" + std::to_string(index),
      "--heartbeat", SecondsText(options_.heartbeat_interval)};
  if (!options_.curve_keys.empty()) {
    arguments.push_back("--curve-keys");
    arguments.push_back(options_.curve_keys);
  }
  std::vector<char*> argv;
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  // Ctrl-C and SIGTERM are held back across fork, so that none reaches the child with this program's handler
  // before it has its own process group and the default handlers.
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  const pid_t pid = fork();
  if (pid == 0) {  // the child: only async-signal-safe calls until exec
    // Its own process group: a terminal's ^C goes to the foreground group, this program's, and must not end the
    // workers under the batch (issue 47); this program stops them (StopWorkers) once it has written what it has.
    setpgid(0, 0);
    // And it dies with this thread, the one that forks (PR_SET_PDEATHSIG follows the parent thread, not the
    // process: LocalCluster is made and destroyed on one thread), whatever its process group.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    struct sigaction default_action = {};
    default_action.sa_handler = SIG_DFL;
    sigemptyset(&default_action.sa_mask);
    sigaction(SIGINT, &default_action, nullptr);
    sigaction(SIGTERM, &default_action, nullptr);
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    const int null_fd = open("/dev/null", O_RDWR);
    dup2(null_fd, STDIN_FILENO);
    dup2(null_fd, STDOUT_FILENO);
    dup2(log_fd_, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const int fork_errno = errno;
  if (pid > 0) {
    // The same from this side, the usual pair: whichever runs first, the group exists before anyone signals it
    // (EACCES, once the child has exec'd, is harmless).
    setpgid(pid, pid);
    AddWorkerGroup(pid);
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (pid < 0) throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(fork_errno));
  return pid;
}

int LocalCluster::workers_exited() {
  int exited = 0;
  for (pid_t& pid : workers_) {
    if (pid > 0 && waitpid(pid, nullptr, WNOHANG) == pid) {
      RemoveWorkerGroup(pid);
      pid = -1;
    }
    if (pid < 0) ++exited;
  }
  return exited;
}

void LocalCluster::StopWorkers() {
  for (pid_t pid : workers_) {
    if (pid > 0) kill(pid, SIGTERM);  // the worker finishes the job in hand and leaves
  }
  const Clock::time_point deadline = Clock::now() + (InterruptRequested() ? kInterruptedStopGrace : kStopGrace);
  for (pid_t& pid : workers_) {
    while (pid > 0) {
      if (waitpid(pid, nullptr, WNOHANG) == pid) {  // its simulation process dies with it (PR_SET_PDEATHSIG)
        RemoveWorkerGroup(pid);
        pid = -1;
      } else if (Clock::now() > deadline) {
        kill(-pid, SIGKILL);  // the worker and its simulation processes
        waitpid(pid, nullptr, 0);
        RemoveWorkerGroup(pid);
        pid = -1;
      } else {
        usleep(10000);  // polling a child's exit: there is no portable way to wait on several with a timeout
      }
    }
  }
}

}  // namespace orcs::runtime
