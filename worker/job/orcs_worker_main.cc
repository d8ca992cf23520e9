// orcs-worker: a headless simulation worker. Connects to a broker, holds credit for a few jobs, runs them one
// at a time (worker/job/job_translation.h) and returns their results; heartbeats and reconnection happen in
// the connection's own thread (worker/broker_connection.h). Serves until SIGINT or SIGTERM.
//
// Each job runs in a sandboxed simulation process (worker/job/simulation_sandbox.h): the same program started
// again as `orcs-worker --sandbox-child`, a hidden mode nobody types, so that a crash in the physics engine costs
// one job (status CRASHED), not the worker. `--no-sandbox` runs jobs in this process, as before issue 7.
//
//   orcs-worker --connect tcp://127.0.0.1:5556 [--credit 2] [--short-job-credit 16] [--id NAME] [--heartbeat SECONDS]
//               [--curve-keys DIR]
//               [--memory-limit MIB] [--no-sandbox]
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <csignal>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "worker/broker_connection.h"
#include "net/cli_style.h"
#include "worker/job/job_translation.h"
#include "worker/job/plugin_loader.h"
#include "worker/job/sandbox_child.h"
#include "worker/job/simulation_sandbox.h"

namespace {

std::atomic<bool> stop_requested{false};

extern "C" void OnSignal(int) { stop_requested.store(true); }

// Each simulation process's address space, MiB: 16 times what the largest shipped scenario needs with a full log
// and recording, and far below a cluster node's memory (docs/reliability.md "Hostile and careless input").
constexpr std::uint64_t kDefaultMemoryLimitMib = 2048;

// How long NextJob waits before looking at the stop flag again.
constexpr std::chrono::milliseconds kPollInterval{200};

// /proc/self/exe: this very binary, even if a rebuild has replaced the file since the worker started. The simulation
// process loads the worker's plug-ins again (a process of its own, a registry of its own).
std::vector<std::string> SandboxArguments(const std::string& plugins) {
  std::vector<std::string> arguments = {"/proc/self/exe", "--sandbox-child"};
  if (!plugins.empty()) arguments.insert(arguments.end(), {"--plugins", plugins});
  return arguments;
}

// The simulation process: `--sandbox-child [--plugins DIR]`.
int SandboxChildMain(int argc, char** argv) {
  orcs::script::PluginRegistry registry;
  if (argc == 4 && std::string_view(argv[2]) == "--plugins") {
    try {
      orcs::worker::LoadPlugins(argv[3], registry);
    } catch (const std::exception& error) {
      std::cerr << "orcs-worker (simulation process): " << error.what() << "\n";
      return orcs::cli::kExitBadInput;
    }
    return orcs::worker::RunSandboxChild(orcs::worker::kSandboxChannelFd, &registry);
  }
  return orcs::worker::RunSandboxChild(orcs::worker::kSandboxChannelFd);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string_view(argv[1]) == "--sandbox-child") return SandboxChildMain(argc, argv);
  orcs::worker::WorkerConnectionOptions options;
  CLI::App app{"orcs-worker: runs simulation jobs from a broker", "orcs-worker"};
  app.add_option("--connect", options.endpoint, "the broker's worker endpoint, e.g. tcp://127.0.0.1:5556")
      ->required()
      ->check(orcs::cli::Endpoint());
  app.add_option("--credit", options.credit, "jobs held at once (queued at the worker)")->check(CLI::Range(1, 64));
  app.add_option("--short-job-credit", options.short_job_credit,
                 "credit after 16 jobs in a row shorter than 1 ms (default 16; <= --credit keeps it fixed)")
      ->check(CLI::Range(0, 1024));
  app.add_option("--id", options.worker_id, "worker name in results (default: host-pid)");
  double heartbeat_seconds = 1.0;
  app.add_option("--heartbeat", heartbeat_seconds,
                 "seconds between heartbeats (default 1; the broker waits for the slower of its pace and this)")
      ->check(orcs::cli::NumberIn(0.001, 3600.0));
  app.add_option("--curve-keys", options.curve_keys,
                 "folder with worker.key, worker.pub and broker.pub: connect with CURVE (docs/security.md)")
      ->check(CLI::Validator([](const std::string& dir) { return dir.empty() ? "needs a folder" : ""; }, "DIR"));
  std::uint64_t memory_limit_mib = kDefaultMemoryLimitMib;
  app.add_option("--memory-limit", memory_limit_mib,
                 "MiB of address space each simulation process may use; a job past it is CRASHED (default " +
                     std::to_string(kDefaultMemoryLimitMib) + "; 0 = no limit)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 30));
  std::string plugins;
  app.add_option("--plugins", plugins,
                 "folder of plug-in libraries (lib*.so, docs/extending.md \"Plug-ins\"): compiled controllers and "
                 "fitness terms that jobs may name");
  bool no_sandbox = false;
  app.add_flag("--no-sandbox", no_sandbox, "run jobs in this process: a crash in the physics ends the worker");
  if (const int exit_code = orcs::cli::ParseArguments(app, argc, argv, {"connect"}); exit_code >= 0) {
    return exit_code;
  }
  options.heartbeat_interval = std::chrono::milliseconds(std::lround(heartbeat_seconds * 1000.0));
  options.log = [](std::string_view line) { std::cerr << "orcs-worker: " << line << "\n"; };

  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);

  std::unique_ptr<orcs::worker::SimulationSandbox> sandbox;
  std::unique_ptr<orcs::worker::WorkerConnection> connection;
  orcs::script::PluginRegistry registry;  // loaded here too: a bad plug-in stops the worker before its first job
  try {
    if (!plugins.empty()) {
      plugins = std::filesystem::absolute(plugins).string();
      orcs::worker::LoadPlugins(plugins, registry);
      std::string names;
      for (const std::string& component : registry.components()) names += " " + component;
      options.log("plug-ins from " + plugins + ":" + (names.empty() ? " none" : names));
    }
    if (!no_sandbox) {
      sandbox = std::make_unique<orcs::worker::SimulationSandbox>(
          SandboxArguments(plugins), orcs::worker::SandboxLimits{.memory_bytes = memory_limit_mib << 20});
    }
    connection = std::make_unique<orcs::worker::WorkerConnection>(options);
  } catch (const std::exception& error) {
    std::cerr << "orcs-worker: " << error.what() << "\n";
    return orcs::cli::kExitBadInput;
  }
  while (!stop_requested.load()) {
    std::optional<orcs::v1::Job> job = connection->NextJob(kPollInterval);
    if (!job) continue;
    // A revoked job (its batch ended) stops at once in the sandbox; its result is then dropped by SendResult.
    const orcs::worker::RunStop revoked{connection->revoked_fd(), [&] { return connection->Revoked(*job); }};
    orcs::v1::Result result = sandbox ? sandbox->Run(*job, revoked) : orcs::worker::RunJob(*job, false, &registry);
    if (result.status() == orcs::v1::Result::CRASHED) {
      options.log("job " + job->job_id() + ": " + result.message() + "; the next job gets a new one");
    }
    connection->SendResult(std::move(result));
  }
  return orcs::cli::kExitOk;
}
