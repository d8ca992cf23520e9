// orcs-osp: a live, headless simulation served over OSP 1.1 (docs/osp.md), so that the original's evolution
// environments, slider tools and network evaluators drive it unchanged, and ODCP 1.0 for each agent in the same
// thread, so that motion editors and slider tools move them directly. Prints "orcs-osp osp=ADDRESS:PORT" on
// stdout once it listens, then one "orcs-osp odcp AGENT=ADDRESS:PORT" line per agent; logs events on stderr;
// serves until SIGINT or SIGTERM.
//
//   orcs-osp [-env FILE] [-ival FILE]... [-val FILE]... [-play AGENT RECORD]... [-port 45454]
//            [-odcp_port 45453] [--bind 127.0.0.1] [--client-timeout 10] [--record DIR] [-gui [--view-port P]]
#include <CLI/CLI.hpp>
#include <csignal>
#include <iostream>

#include "model/core/error.h"
#include "net/cli_style.h"
#include "model/core/text.h"
#include "worker/osp/episode_recorder.h"
#include "worker/osp/osp_gateway.h"
#include "worker/osp/protocol_values.h"
#include "worker/view_launch.h"
#include "worker/played_records.h"
#include "model/scene/world_setup.h"

namespace {

orcs::osp::OspGateway* running_gateway = nullptr;

extern "C" void OnSignal(int) {
  if (running_gateway != nullptr) running_gateway->Stop();  // async-signal-safe: one write()
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
  bool gui = false;    // -gui: orcs-view --live --osp on this world
  int view_port = -1;  // --view-port: orcs-view's HTTP port with -gui; -1 = its default (8765)
};

int Serve(const OspOptions& options) {
  orcs::scene::Simulation simulation;
  // The original's port values, so that a value file can set them as it could there.
  orcs::osp::AddProtocolValues(simulation.repository());
  const orcs::IgnoredValues ignored =
      orcs::scene::SetUpWorld(simulation, options.environment, options.initial_value_files, options.value_files,
                              options.strict ? orcs::UnknownPaths::kRefuse : orcs::UnknownPaths::kIgnore);
  if (!ignored.empty()) std::cerr << "orcs-osp: " << ignored.Warning() << "\n";
  simulation.Reset(0);
  std::vector<orcs::control::KeyframePlayer> players = orcs::MakePlayers(options.play, simulation, "orcs-osp");
  std::unique_ptr<orcs::osp::EpisodeRecorder> recorder;
  if (!options.record.empty()) {
    recorder = std::make_unique<orcs::osp::EpisodeRecorder>(
        simulation, orcs::osp::EpisodeRecorderOptions{.folder = options.record,
                                                      .environment = options.environment,
                                                      .log = [](std::string_view line) {
                                                        std::cerr << "orcs-osp: " << line << std::endl;
                                                      }});
  }
  orcs::osp::OspGatewayOptions gateway_options;
  gateway_options.port = options.port;
  gateway_options.odcp_port = options.odcp_port;
  gateway_options.bind_address = options.bind_address;
  gateway_options.client_timeout_seconds = options.client_timeout_seconds;
  gateway_options.before_step = [&players](double time) {
    for (orcs::control::KeyframePlayer& player : players) player.Apply(time);
  };
  if (recorder) gateway_options.after_step = [&recorder] { recorder->Sample(); };
  gateway_options.after_reset = [&players, &recorder] {
    for (orcs::control::KeyframePlayer& player : players) player.Reset();  // the record starts again at time 0
    if (recorder) recorder->NextEpisode();
  };
  orcs::osp::OspGateway gateway(simulation, std::move(gateway_options));
  running_gateway = &gateway;
  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  for (const std::string& line : gateway.EndpointLines("orcs-osp")) std::cout << line << std::endl;
  gateway.Run();
  running_gateway = nullptr;
  return orcs::cli::kExitOk;
}

// -gui: the original ClientSimulator's -gui. orcs-view's live mode serves the same world to the browser while OSP
// clients drive it (orcs-view --live --osp, docs/viewer.md).
int LaunchGui(const char* argv0, const OspOptions& options) {
  std::vector<std::string> arguments = {"--osp"};
  if (!options.environment.empty()) arguments.insert(arguments.end(), {"--env", options.environment});
  for (const std::string& file : options.initial_value_files) arguments.insert(arguments.end(), {"--ival", file});
  for (const std::string& file : options.value_files) arguments.insert(arguments.end(), {"--val", file});
  if (options.strict) arguments.push_back("--strict");
  if (options.port >= 0) arguments.insert(arguments.end(), {"--osp-port", std::to_string(options.port)});
  if (options.odcp_port >= 0) arguments.insert(arguments.end(), {"--odcp-port", std::to_string(options.odcp_port)});
  arguments.insert(arguments.end(), {"--osp-bind", options.bind_address, "--client-timeout",
                                     orcs::text::FormatDouble(options.client_timeout_seconds)});
  if (!options.record.empty()) arguments.insert(arguments.end(), {"--record", options.record});
  if (options.view_port >= 0) arguments.insert(arguments.end(), {"--port", std::to_string(options.view_port)});
  return orcs::ReplaceWithLiveView(argv0, "orcs-osp", arguments);
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
  app.add_flag("--gui", options.gui,
               "serve the world to orcs-view's page while OSP clients drive it (orcs-view --live --osp; the "
               "original ClientSimulator's -gui; -gui also accepted)");
  app.add_option("--view-port", options.view_port, "with -gui: orcs-view's HTTP port (default 8765; 0 = any)")
      ->check(CLI::Range(0, 65535));
  const auto validate = [&options] {
    if (options.gui && !options.play.empty()) {
      throw CLI::ValidationError("-play", "not with -gui yet: play the record from an OSP client, or run without -gui");
    }
    if (!options.gui && options.view_port >= 0) throw CLI::ValidationError("--view-port", "only with -gui");
  };
  if (const int exit_code = orcs::cli::ParseArguments(app, argc, argv,
                                                      {"env", "ival", "val", "play", "port", "odcp_port", "gui"}, validate);
      exit_code >= 0) {
    return exit_code;
  }
  if (options.gui) return LaunchGui(argv[0], options);
  return orcs::cli::RunProgram("orcs-osp", [&] { return Serve(options); });
}
