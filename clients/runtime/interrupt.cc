#include "clients/runtime/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace orcs::runtime {
namespace {

// Everything the handler touches is a lock-free atomic or a plain buffer published through one: async-signal-safe.
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<pid_t>::is_always_lock_free &&
              std::atomic<std::size_t>::is_always_lock_free && std::atomic<bool>::is_always_lock_free);

std::atomic<bool> interrupted{false};
std::atomic<int> signals_seen{0};
std::atomic<bool> caught{false};

constexpr std::size_t kMaxGroups = 4096;
std::atomic<pid_t> worker_groups[kMaxGroups];  // 0 = a free slot

constexpr std::size_t kMaxHint = 1024;
char hint[kMaxHint];
std::atomic<std::size_t> hint_size{0};
std::atomic<bool> hint_set{false};  // by SetInterruptHint; else CatchInterrupts sets "PROGRAM: stopped at once"

void WriteAll(const char* text, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(STDERR_FILENO, text, size);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return;
    text += written;
    size -= static_cast<std::size_t>(written);
  }
}

extern "C" void OnInterrupt(int) {
  const int saved_errno = errno;
  if (signals_seen.fetch_add(1) == 0) {  // the first: the waiting loops stop and the command ends in order
    interrupted.store(true);
    errno = saved_errno;
    return;
  }
  // The second: now. The workers first, so that none outlives this process.
  for (std::atomic<pid_t>& group : worker_groups) {
    const pid_t leader = group.load();
    if (leader > 0) ::kill(-leader, SIGKILL);
  }
  WriteAll("\n", 1);
  WriteAll(hint, std::min(hint_size.load(), kMaxHint));
  ::_exit(kExitInterrupted);
}

bool SafeInWord(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::strchr("-_./=:@%+,", c) != nullptr;
}

}  // namespace

void CatchInterrupts() {
  if (caught.exchange(true)) return;
  if (!hint_set.load()) {
    SetInterruptHint(std::string(program_invocation_short_name) + ": stopped at once (a second Ctrl-C)");
  }
  struct sigaction action = {};
  action.sa_handler = OnInterrupt;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);  // one handler at a time: the count decides what it does
  sigaddset(&action.sa_mask, SIGTERM);
  action.sa_flags = SA_RESTART;  // file writes are not cut short; the waits are bounded and poll the flag
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

const std::atomic<bool>& InterruptFlag() { return interrupted; }

void SetInterruptHint(const std::string& line) {
  hint_set.store(true);
  hint_size.store(0);
  const std::string text = line.empty() || line.back() == '\n' ? line : line + "\n";
  const std::size_t size = std::min(text.size(), kMaxHint);
  std::memcpy(hint, text.data(), size);
  hint_size.store(size);
}

void AddWorkerGroup(pid_t group) {
  if (group <= 0) return;
  for (std::atomic<pid_t>& slot : worker_groups) {
    pid_t free = 0;
    if (slot.compare_exchange_strong(free, group)) return;
  }
}

void RemoveWorkerGroup(pid_t group) {
  if (group <= 0) return;
  for (std::atomic<pid_t>& slot : worker_groups) {
    pid_t expected = group;
    if (slot.compare_exchange_strong(expected, 0)) return;
  }
}

std::string ShellCommand(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& word : words) {
    if (!line.empty()) line += ' ';
    if (!word.empty() && std::all_of(word.begin(), word.end(), SafeInWord)) {
      line += word;
      continue;
    }
    line += '\'';
    for (char c : word) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

void SetInterruptForTest(bool value) {
  interrupted.store(value);
  signals_seen.store(value ? 1 : 0);
}

}  // namespace orcs::runtime
