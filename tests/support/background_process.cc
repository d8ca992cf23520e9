#include "tests/support/background_process.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace orcs::test_support {
namespace {

using Clock = std::chrono::steady_clock;

void Check(int error, const std::string& what) {
  if (error != 0) throw std::runtime_error(what + ": " + std::strerror(error));
}

int MillisecondsUntil(Clock::time_point deadline) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left < 0 ? 0 : static_cast<int>(left);
}

}  // namespace

BackgroundProcess::BackgroundProcess(const std::vector<std::string>& argv, bool own_process_group)
    : own_group_(own_process_group) {
  if (argv.empty()) throw std::invalid_argument("BackgroundProcess: empty argv");
  std::vector<char*> args;
  for (const std::string& argument : argv) args.push_back(const_cast<char*>(argument.c_str()));
  args.push_back(nullptr);

  int out_pipe[2];
  int err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe2: ") + std::strerror(errno));
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    throw std::runtime_error(std::string("pipe2: ") + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  int error = posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (error == 0) error = posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  if (error == 0) error = posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (error == 0 && own_process_group) error = posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  if (error == 0 && own_process_group) error = posix_spawnattr_setpgroup(&attributes, 0);  // a group of its own
  if (error == 0) error = posix_spawn(&pid_, args[0], &actions, &attributes, args.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  out_fd_ = out_pipe[0];
  err_fd_ = err_pipe[0];
  if (error != 0) {
    ::close(out_fd_);
    ::close(err_fd_);
    pid_ = -1;
    Check(error, "posix_spawn " + argv[0]);
  }
}

BackgroundProcess::~BackgroundProcess() {
  if (pid_ > 0 && !result_) {
    ::kill(own_group_ ? -pid_ : pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (out_fd_ >= 0) ::close(out_fd_);
  if (err_fd_ >= 0) ::close(err_fd_);
}

void BackgroundProcess::Pump(int timeout_ms) {
  pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
  std::string* sinks[2] = {&out_, &err_};
  int* owners[2] = {&out_fd_, &err_fd_};
  if (out_fd_ < 0 && err_fd_ < 0) return;
  if (::poll(fds, 2, timeout_ms) <= 0) return;
  char buffer[4096];
  for (int i = 0; i < 2; ++i) {
    if (fds[i].fd < 0 || fds[i].revents == 0) continue;
    const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
    if (n > 0) {
      sinks[i]->append(buffer, static_cast<size_t>(n));
    } else if (n == 0 || errno != EINTR) {  // end of file: poll ignores negative descriptors from now on
      ::close(*owners[i]);
      *owners[i] = -1;
    }
  }
}

std::optional<std::string> BackgroundProcess::ReadLine(std::chrono::milliseconds timeout) {
  const Clock::time_point deadline = Clock::now() + timeout;
  while (true) {
    const std::size_t newline = out_.find('\n');
    if (newline != std::string::npos) {
      std::string line = out_.substr(0, newline);
      out_.erase(0, newline + 1);
      return line;
    }
    if (out_fd_ < 0 || Clock::now() >= deadline) return std::nullopt;
    Pump(MillisecondsUntil(deadline));
  }
}

void BackgroundProcess::Signal(int signal) {
  if (pid_ > 0 && !result_) ::kill(pid_, signal);
}

void BackgroundProcess::SignalGroup(int signal) {
  if (own_group_ && pid_ > 0 && !result_) ::kill(-pid_, signal);
}

std::optional<ProcessResult> BackgroundProcess::Wait(std::chrono::milliseconds timeout) {
  if (result_) return result_;
  const Clock::time_point deadline = Clock::now() + timeout;
  while (true) {
    int status = 0;
    const pid_t reaped = ::waitpid(pid_, &status, WNOHANG);
    if (reaped == pid_) {
      while (out_fd_ >= 0 || err_fd_ >= 0) Pump(1000);  // the rest of its output
      ProcessResult result;
      if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
      result.out = out_;
      result.err = err_;
      out_.clear();
      result_ = result;
      return result_;
    }
    if (reaped < 0 && errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    if (Clock::now() >= deadline) return std::nullopt;
    // Keep the pipes flowing (a child blocked on a full pipe never exits); wake at least every 10 ms to reap.
    Pump(std::min(10, MillisecondsUntil(deadline)));
    if (out_fd_ < 0 && err_fd_ < 0) {
      pollfd none{-1, 0, 0};
      ::poll(&none, 1, std::min(10, MillisecondsUntil(deadline)));
    }
  }
}

const std::string& BackgroundProcess::err() {
  Pump(0);
  return err_;
}

}  // namespace orcs::test_support
