#include "clients/batch/local_cluster.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "net/curve_keys.h"

namespace orcs::batch {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// How long stopped workers get to finish the job in hand before SIGKILL.
constexpr std::chrono::milliseconds kStopGrace{3000};

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
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
  if (pid == 0) {  // the child: only async-signal-safe calls until exec
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    const int null_fd = open("/dev/null", O_RDWR);
    dup2(null_fd, STDIN_FILENO);
    dup2(null_fd, STDOUT_FILENO);
    dup2(log_fd_, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int LocalCluster::workers_exited() {
  int exited = 0;
  for (pid_t& pid : workers_) {
    if (pid > 0 && waitpid(pid, nullptr, WNOHANG) == pid) pid = -1;
    if (pid < 0) ++exited;
  }
  return exited;
}

void LocalCluster::StopWorkers() {
  for (pid_t pid : workers_) {
    if (pid > 0) kill(pid, SIGTERM);
  }
  const Clock::time_point deadline = Clock::now() + kStopGrace;
  for (pid_t& pid : workers_) {
    while (pid > 0) {
      if (waitpid(pid, nullptr, WNOHANG) == pid) {
        pid = -1;
      } else if (Clock::now() > deadline) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
        pid = -1;
      } else {
        usleep(10000);  // polling a child's exit: there is no portable way to wait on several with a timeout
      }
    }
  }
}

}  // namespace orcs::batch
