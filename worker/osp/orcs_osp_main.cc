// orcs-osp: a live, headless simulation served over OSP 1.1 (docs/osp.md), so that the original's evolution
// environments, slider tools and network evaluators drive it unchanged, and ODCP 1.0 for each agent in the same
// thread, so that motion editors and slider tools move them directly. Prints "orcs-osp osp=ADDRESS:PORT" on
// stdout once it listens, then one "orcs-osp odcp AGENT=ADDRESS:PORT" line per agent; logs events on stderr;
// serves until SIGINT or SIGTERM.
//
//   orcs-osp [-env FILE] [-ival FILE]... [-val FILE]... [-play AGENT RECORD]... [-port 45454]
//            [-odcp_port 45453] [--bind 127.0.0.1] [--client-timeout 10] [--record DIR]
#include <CLI/CLI.hpp>
#include <csignal>
#include <iostream>

#include "model/core/error.h"
#include "net/cli_style.h"
#include "worker/osp/episode_recorder.h"
#include "worker/osp/odcp_server.h"
#include "worker/osp/osp_server.h"
#include "worker/osp/protocol_values.h"
#include "worker/sim/played_records.h"
#include "model/scene/world_setup.h"

namespace {

orcs::osp::OspServer* running_server = nullptr;

extern "C" void OnSignal(int) {
  if (running_server != nullptr) running_server->Stop();  // async-signal-safe: one write()
}

struct OspOptions {
  std::string environment;
  std::vector<std::string> initial_value_files;
  std::vector<std::string> value_files;
  bool strict = false;  // --strict: a value file's path orcs lacks is an error, not a warning
  std::vector<std::pair<std::string, std::string>> play;  // -play AGENT RECORD...
  int port = -1;  // -1: /UDPCommunication/ServerPort
  int odcp_port = -1;  // base port of the ODCP servers; -1: /SimpleUdpMotorInterface/ServerPort
  std::string bind_address = "127.0.0.1";
  double client_timeout_seconds = 10.0;
  std::string record;  // --record DIR: one recording per episode, "" = none
};

// The port of an option, or of its repository value when the option was not given; InputError when out of range.
int PortOf(int option, const orcs::VariableRepository& repository, std::string_view path) {
  const std::int64_t port = option >= 0 ? option : repository.Get(path).as_int();
  if (port < 0 || port > 65535) {
    throw orcs::InputError(std::string(path), 0, "expected a port 0..65535, found " + std::to_string(port));
  }
  return static_cast<int>(port);
}

// One ODCP server per agent (docs/osp.md, "Ports"), served in the OSP server's thread; a line on stdout each.
struct OdcpServers {
  std::vector<std::unique_ptr<orcs::osp::AgentMotors>> motors;  // what each server drives (outlives it)
  std::vector<std::unique_ptr<orcs::osp::OdcpServer>> servers;  // by agent index
};

OdcpServers StartOdcp(orcs::scene::Simulation& simulation, orcs::osp::OspServer& osp, const OspOptions& options) {
  OdcpServers odcp;
  const int base = PortOf(options.odcp_port, simulation.repository(), orcs::osp::kOdcpServerPortPath);
  try {
    const std::vector<std::uint16_t> ports = orcs::osp::OdcpPorts(base, simulation.agent_count(), osp.endpoint().port);
    for (int a = 0; a < simulation.agent_count(); ++a) {
      odcp.motors.push_back(std::make_unique<orcs::osp::AgentMotors>(
          orcs::osp::MakeAgentInterface(simulation, a),
          simulation.repository().Find(orcs::osp::kOdcpReportGoalAnglesPath)));
      orcs::osp::OdcpServerOptions server_options;
      server_options.bind_address = options.bind_address;
      server_options.port = ports[static_cast<std::size_t>(a)];
      server_options.name = "orcs-osp: ODCP " + odcp.motors.back()->name();
      odcp.servers.push_back(std::make_unique<orcs::osp::OdcpServer>(*odcp.motors.back(), server_options));
      osp.AddService(odcp.servers.back().get());
    }
  } catch (const std::runtime_error& error) {  // a port in use or beyond 65535: bad input
    throw orcs::InputError(std::string("-odcp_port: ") + error.what());
  }
  return odcp;
}

int Serve(const OspOptions& options) {
  orcs::scene::Simulation simulation;
  // The original's port values, so that a value file can set them as it could there.
  orcs::osp::AddProtocolValues(simulation.repository());
  const orcs::IgnoredValues ignored =
      orcs::scene::SetUpWorld(simulation, options.environment, options.initial_value_files, options.value_files,
                              options.strict ? orcs::UnknownPaths::kRefuse : orcs::UnknownPaths::kIgnore);
  if (!ignored.empty()) std::cerr << "orcs-osp: " << ignored.Warning() << "\n";
  simulation.Reset(0);
  std::vector<orcs::control::KeyframePlayer> players = orcs::sim::MakePlayers(options.play, simulation, "orcs-osp");
  orcs::osp::OspServerOptions server_options;
  server_options.bind_address = options.bind_address;
  server_options.port =
      static_cast<std::uint16_t>(PortOf(options.port, simulation.repository(), orcs::osp::kOspServerPortPath));
  server_options.client_timeout = std::chrono::milliseconds(std::lround(options.client_timeout_seconds * 1000.0));
  server_options.before_step = [&players](double time) {
    for (orcs::control::KeyframePlayer& player : players) player.Apply(time);
  };
  std::unique_ptr<orcs::osp::EpisodeRecorder> recorder;
  if (!options.record.empty()) {
    recorder = std::make_unique<orcs::osp::EpisodeRecorder>(
        simulation, orcs::osp::EpisodeRecorderOptions{.folder = options.record,
                                                      .environment = options.environment,
                                                      .log = [](std::string_view line) {
                                                        std::cerr << "orcs-osp: " << line << std::endl;
                                                      }});
    server_options.after_step = [&recorder] { recorder->Sample(); };
  }
  server_options.after_reset = [&players, &recorder] {
    for (orcs::control::KeyframePlayer& player : players) player.Reset();  // the record starts again at time 0
    if (recorder) recorder->NextEpisode();
  };
  std::unique_ptr<orcs::osp::OspServer> server;
  try {
    server = std::make_unique<orcs::osp::OspServer>(simulation, server_options);
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound: bad input
    throw orcs::InputError(error.what());
  }
  const OdcpServers odcp = StartOdcp(simulation, *server, options);
  running_server = server.get();
  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::cout << "orcs-osp osp=" << server->endpoint().ToString() << std::endl;
  for (std::size_t a = 0; a < odcp.servers.size(); ++a) {
    std::cout << "orcs-osp odcp " << odcp.motors[a]->name() << "=" << odcp.servers[a]->endpoint().ToString()
              << std::endl;
  }
  server->Run();
  running_server = nullptr;
  return orcs::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  OspOptions options;
  CLI::App app{"orcs-osp: a headless simulation served over OSP 1.1 (UDP)", "orcs-osp"};
  app.add_option("--env", options.environment, "ORCS XML environment file (-env also accepted)");  // checked as read
  app.add_option("--ival", options.initial_value_files, "value file loaded before the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--val", options.value_files, "value file loaded after the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_flag("--strict", options.strict,
               "refuse a value file naming a path orcs lacks (default: ignore it with a warning)");
  app.add_option("--play", options.play,
                 "AGENT RECORD: play a keyframe record into the agent's inputs in simulated time, as the clients "
                 "step (repeatable, one per agent; -play also accepted)")
      ->allow_extra_args(false);
  app.add_option("--port", options.port, "OSP server port (default /UDPCommunication/ServerPort, 45454; 0 = any)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--odcp_port,--odcp-port", options.odcp_port,
                 "base port of the ODCP servers, one per agent, skipping the OSP port (default "
                 "/SimpleUdpMotorInterface/ServerPort, 45453; 0 = any)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--bind", options.bind_address, "interface to listen on (default 127.0.0.1; * = every interface)");
  app.add_option("--record", options.record,
                 "folder for one recording per episode (reset to reset): episode-0001.orcsrec, ... for orcs-view");
  app.add_option("--client-timeout", options.client_timeout_seconds,
                 "seconds of silence after which a client loses its agents (default 10)")
      ->check(orcs::cli::NumberIn(0.001, 1e6));
  if (const int exit_code = orcs::cli::ParseArguments(app, argc, argv, {"env", "ival", "val", "play", "port", "odcp_port"}); exit_code >= 0) {
    return exit_code;
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
