// The sandboxed simulation process: `orcs-worker --sandbox-child`, started by SimulationSandbox
// (worker/job/simulation_sandbox.h), never by a user. It reads serialised jobs from the channel on a descriptor,
// runs each (with the scenario's "fault" test hook honoured) and writes the serialised result back, until the
// worker closes the channel. If the physics crashes, only this process dies.
#pragma once

#include "model/script/plugin_registry.h"

namespace orcs::worker {

/// The descriptor on which the simulation process finds its channel to the worker.
inline constexpr int kSandboxChannelFd = 3;

/// Serves jobs on `fd` (a FrameChannel) until the other end closes; returns the process's exit code: 0 when the
/// worker closed the channel, 3 when `fd` is not a socket or a message was not a job (after one line on stderr). The
/// process dies with SIGKILL when the thread that started it ends, and ignores SIGINT and SIGTERM: the worker decides
/// when it stops.
/// `plugins`: the worker's plug-in components, loaded again in this process (null: none).
int RunSandboxChild(int fd, const script::PluginRegistry* plugins = nullptr);

}  // namespace orcs::worker
