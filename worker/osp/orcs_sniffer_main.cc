// orcs-sniffer: the KeyFrameSniffer (docs/osp.md). Listens where a motion editor sends ODCP 1.0 commands,
// answers connect and get-motors as the simulator would, records every set-motors command with its receipt time
// into a keyframe record, and writes FILE (atomically) when the editor disconnects, or on SIGINT/SIGTERM. Prints
// "orcs-sniffer odcp=ADDRESS:PORT" once it listens and one summary line when done.
//
//   orcs-sniffer FILE [-port 45453] [--bind 127.0.0.1] [--motors 21]
//
// The record replays with `orcs-sim -play AGENT FILE`.
#include <poll.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "net/cli_style.h"
#include "worker/osp/keyframe_sniffer.h"
#include "worker/osp/odcp_server.h"

namespace {

volatile std::sig_atomic_t stop_requested = 0;

extern "C" void OnSignal(int) { stop_requested = 1; }

struct SnifferOptions {
  std::string file;                        // where the record goes
  int port = 45453;                        // the ODCP port (0 = any)
  std::string bind_address = "127.0.0.1";  // interface to listen on
  int motors = 21;                         // motors per row (the A-Series has 21)
};

// Serves until the editor disconnects after a command, or a signal.
void Serve(orcs::osp::OdcpServer& server, const orcs::osp::KeyframeSniffer& sniffer) {
  pollfd entry{server.fd(), POLLIN, 0};
  while (!sniffer.finished() && stop_requested == 0) {
    entry.revents = 0;
    if (poll(&entry, 1, 100) > 0 && (entry.revents & POLLIN) != 0) server.OnReadable();
  }
}

int Sniff(const SnifferOptions& options) {
  orcs::AtomicFile file(options.file);  // fails now, not after the recording, when FILE cannot be written
  orcs::osp::KeyframeSniffer sniffer(options.motors);
  orcs::osp::OdcpServerOptions server_options;
  server_options.bind_address = options.bind_address;
  server_options.port = static_cast<std::uint16_t>(options.port);
  server_options.name = "orcs-sniffer";
  std::unique_ptr<orcs::osp::OdcpServer> server;
  try {
    server = std::make_unique<orcs::osp::OdcpServer>(sniffer, server_options);
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound: bad input
    throw orcs::InputError(std::string("-port: ") + error.what());
  }
  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::cout << "orcs-sniffer odcp=" << server->endpoint().ToString() << std::endl;
  Serve(*server, sniffer);
  const orcs::control::KeyframeRecord& record = sniffer.record();
  if (record.frames.empty()) {
    std::cerr << "orcs-sniffer: no set-motors command arrived; " << options.file << " not written\n";
    return orcs::cli::kExitRunFailed;
  }
  file.stream() << orcs::control::FormatKeyframeRecord(
      record, {"KeyFrameSniffer record written by orcs-sniffer from ODCP set-motors commands on " +
                   server->endpoint().ToString(),
               "time: ms since the first command; then DesiredAngle (degrees), DesiredTorque (0...1) per motor"});
  file.Commit();
  const orcs::osp::OdcpServerStats& stats = server->stats();
  std::printf("recorded %zu keyframes over %.3f s into %s (%llu datagrams ignored, %llu words clamped)\n",
              record.frames.size(), record.frames.back().time_ms / 1000.0, options.file.c_str(),
              static_cast<unsigned long long>(stats.datagrams_ignored),
              static_cast<unsigned long long>(stats.words_clamped));
  return orcs::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  SnifferOptions options;
  CLI::App app{"orcs-sniffer: records ODCP set-motors commands into a keyframe record", "orcs-sniffer"};
  app.add_option("file", options.file, "the record to write (replay it with orcs-sim -play AGENT FILE)")->required();
  app.add_option("--port", options.port, "ODCP port to listen on (default 45453; 0 = any; -port also accepted)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--bind", options.bind_address, "interface to listen on (default 127.0.0.1; * = every interface)");
  app.add_option("--motors", options.motors, "motors of the agent the editor drives (default 21, the A-Series)")
      ->check(CLI::Range(1, 127));
  if (const int exit_code = orcs::cli::ParseArguments(app, argc, argv, {"port"}); exit_code >= 0) {
    return exit_code;
  }
  return orcs::cli::RunProgram("orcs-sniffer", [&] { return Sniff(options); });
}
