// orcs-osp: a live, headless simulation served over OSP 1.1 (docs/osp.md), so that the original's evolution
// environments, slider tools and network evaluators drive it unchanged. Prints "orcs-osp osp=ADDRESS:PORT" on
// stdout once it listens, logs events on stderr, serves until SIGINT or SIGTERM.
//
//   orcs-osp [-env FILE] [-ival FILE]... [-val FILE]... [-port 45454] [--bind 127.0.0.1] [--client-timeout 10]
#include <CLI/CLI.hpp>
#include <csignal>
#include <iostream>

#include "model/core/error.h"
#include "worker/cli_style.h"
#include "worker/osp/osp_server.h"
#include "worker/sim/world_setup.h"

namespace {

orcs::osp::OspServer* running_server = nullptr;

extern "C" void OnSignal(int) {
  if (running_server != nullptr) running_server->Stop();  // async-signal-safe: one write()
}

struct OspOptions {
  std::string environment;
  std::vector<std::string> initial_value_files;
  std::vector<std::string> value_files;
  int port = -1;  // -1: /UDPCommunication/ServerPort
  std::string bind_address = "127.0.0.1";
  double client_timeout_seconds = 10.0;
};

int Serve(const OspOptions& options) {
  orcs::scene::Simulation simulation;
  // The original's port value, so that a value file can set it as it could there.
  simulation.repository().Add("/UDPCommunication/ServerPort", 45454);
  orcs::sim::SetUpWorld(simulation, options.environment, options.initial_value_files, options.value_files);
  simulation.Reset(0);
  orcs::osp::OspServerOptions server_options;
  server_options.bind_address = options.bind_address;
  const std::int64_t port =
      options.port >= 0 ? options.port : simulation.repository().Get("/UDPCommunication/ServerPort").as_int();
  if (port < 0 || port > 65535) {
    throw orcs::InputError("/UDPCommunication/ServerPort", 0, "expected a port 0..65535, found " + std::to_string(port));
  }
  server_options.port = static_cast<std::uint16_t>(port);
  server_options.client_timeout = std::chrono::milliseconds(std::lround(options.client_timeout_seconds * 1000.0));
  std::unique_ptr<orcs::osp::OspServer> server;
  try {
    server = std::make_unique<orcs::osp::OspServer>(simulation, server_options);
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound: bad input
    throw orcs::InputError(error.what());
  }
  running_server = server.get();
  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::cout << "orcs-osp osp=" << server->endpoint().ToString() << std::endl;
  server->Run();
  running_server = nullptr;
  return orcs::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  OspOptions options;
  CLI::App app{"orcs-osp: a headless simulation served over OSP 1.1 (UDP)", "orcs-osp"};
  app.add_option("--env", options.environment, "ORCS XML environment file (-env also accepted)")
      ->check(CLI::ExistingFile);
  app.add_option("--ival", options.initial_value_files, "value file loaded before the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--val", options.value_files, "value file loaded after the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--port", options.port, "OSP server port (default /UDPCommunication/ServerPort, 45454; 0 = any)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--bind", options.bind_address, "interface to listen on (default 127.0.0.1; * = every interface)");
  app.add_option("--client-timeout", options.client_timeout_seconds,
                 "seconds of silence after which a client loses its agents (default 10)")
      ->check(CLI::Range(0.001, 1e6));
  const std::vector<std::string> arguments =
      orcs::cli::NormaliseSingleDashOptions(argc, argv, {"env", "ival", "val", "port"});
  std::vector<const char*> pointers;
  for (const std::string& argument : arguments) pointers.push_back(argument.c_str());
  try {
    app.parse(static_cast<int>(pointers.size()), pointers.data());
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return orcs::cli::kExitOk;
  } catch (const CLI::ParseError& error) {
    std::cerr << "orcs-osp: " << error.what() << " (see orcs-osp --help)\n";
    return orcs::cli::kExitBadInput;
  }
  try {
    return Serve(options);
  } catch (const orcs::InputError& error) {
    std::cerr << "orcs-osp: " << error.what() << "\n";
    return orcs::cli::kExitBadInput;
  } catch (const std::exception& error) {
    std::cerr << "orcs-osp: internal error: " << error.what() << "\n";
    return orcs::cli::kExitRunFailed;
  }
}
