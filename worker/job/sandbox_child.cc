#include "worker/job/sandbox_child.h"

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <iostream>
#include <string>

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"
#include "worker/job/frame_channel.h"
#include "worker/job/job_translation.h"
#include "worker/job/simulation_sandbox.h"

namespace orcs::worker {
namespace {

// The CPU time this process has used so far, whole seconds rounded up.
rlim_t CpuSecondsUsed() {
  rusage usage = {};
  ::getrusage(RUSAGE_SELF, &usage);
  const double seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
  return static_cast<rlim_t>(std::ceil(seconds));
}

// Bounds the CPU time the coming job may spend (CpuSecondsFor its limit; none without one). The process lives for
// many jobs and RLIMIT_CPU counts its whole life, so the bound is moved on from what it has used so far.
void LimitCpuTime(const v1::Job& job) {
  rlimit cpu = {};
  if (::getrlimit(RLIMIT_CPU, &cpu) != 0) return;
  const std::uint64_t allowance = CpuSecondsFor(job.time_limit_seconds());
  cpu.rlim_cur = allowance == 0 ? cpu.rlim_max : std::min<rlim_t>(cpu.rlim_max, CpuSecondsUsed() + allowance);
  ::setrlimit(RLIMIT_CPU, &cpu);
}

}  // namespace

int RunSandboxChild(int fd, const script::PluginRegistry* plugins) {
  struct stat descriptor = {};
  if (::fstat(fd, &descriptor) != 0 || !S_ISSOCK(descriptor.st_mode)) {  // typed by hand: no worker at the other end
    std::cerr << "orcs-worker: --sandbox-child is started by orcs-worker itself, with its job channel on descriptor "
              << fd << ", which is not a socket here\n";
    return 3;
  }
  // A worker killed with SIGKILL cannot close the channel while a job runs: take the simulation down with it.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  // Ctrl-C and a scheduler's SIGTERM are the worker's to handle (it finishes the job in hand); dying of them here
  // would report that job as crashed.
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  FrameChannel channel(fd);
  std::string in;
  std::string out;
  v1::Job job;
  while (true) {
    const FrameChannel::ReadStatus status = channel.Read(in, std::chrono::steady_clock::time_point::max());
    if (status == FrameChannel::ReadStatus::kClosed) return 0;
    if (status != FrameChannel::ReadStatus::kOk || !job.ParseFromString(in)) {
      std::cerr << "orcs-worker (simulation process): the worker sent something that is not a job; stopping\n";
      return 3;
    }
    LimitCpuTime(job);
    const v1::Result result = RunJob(job, /*inject_faults=*/true, plugins);
    out.clear();
    result.SerializeToString(&out);
    if (!channel.Write(out)) return 0;  // the worker is gone
  }
}

}  // namespace orcs::worker
