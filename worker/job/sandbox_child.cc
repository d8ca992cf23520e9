#include "worker/job/sandbox_child.h"

#include <sys/prctl.h>
#include <sys/stat.h>

#include <csignal>
#include <iostream>
#include <string>

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"
#include "worker/job/frame_channel.h"
#include "worker/job/job_translation.h"

namespace orcs::worker {

int RunSandboxChild(int fd) {
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
    const v1::Result result = RunJob(job, /*inject_faults=*/true);
    out.clear();
    result.SerializeToString(&out);
    if (!channel.Write(out)) return 0;  // the worker is gone
  }
}

}  // namespace orcs::worker
