// orcs-view: serves recordings, batch, evolve and gap folders, or a live simulation, to a browser; renders stills
// and clips (docs/viewer.md).
#include <csignal>
#include <iostream>
#include <memory>
#include <thread>

#include "model/core/error.h"
#include "net/cli_style.h"
#include "viewer/broker_watch.h"
#include "viewer/clip_renderer.h"
#include "viewer/live_session.h"
#include "viewer/view_catalog.h"
#include "viewer/view_options.h"
#include "viewer/view_server.h"
#include "viewer/web_assets.h"

namespace orcs::viewer {
namespace {

sigset_t StopSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  return signals;
}

// Stops the server on SIGINT or SIGTERM: a thread waits for the signals, so no work happens in a handler. Every
// thread must block them, the live session's too, or the kernel could end the process in one (no log finished, no
// recording written): BlockStopSignals() comes before any thread starts.
void BlockStopSignals() {
  const sigset_t signals = StopSignals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
}

std::thread WatchSignals(ViewServer& server) {
  const sigset_t signals = StopSignals();
  return std::thread([signals, &server] {
    int received = 0;
    sigwait(&signals, &received);
    server.Stop();
  });
}

int Serve(const ViewOptions& options) {
  BlockStopSignals();
  const WebAssets assets(options.web_dir);
  std::unique_ptr<ViewCatalog> catalog;
  std::unique_ptr<LiveSession> live;
  std::unique_ptr<BrokerWatch> broker;
  if (options.live) {
    live = std::make_unique<LiveSession>(options.live_options);
  } else if (!options.inputs.empty() || options.broker.empty()) {  // --broker alone: the dashboard only
    catalog = std::make_unique<ViewCatalog>(options.inputs);
  }
  if (!options.broker.empty()) {
    broker = std::make_unique<BrokerWatch>(net::StatusClientOptions{options.broker, options.curve_keys},
                                           std::chrono::milliseconds(1000));
  }
  ViewServer server(assets, catalog.get(), live.get(), nullptr, broker.get());
  for (const std::string& name : options.allow_hosts) server.AllowHost(name);
  const int port = server.Bind(options.bind, options.port);
  std::thread watcher = WatchSignals(server);
  watcher.detach();
  const bool any = options.bind == "0.0.0.0" || options.bind == "::";
  const bool ipv6 = !any && options.bind.find(':') != std::string::npos && !options.bind.starts_with('[');
  const std::string host = any ? "127.0.0.1" : ipv6 ? "[" + options.bind + "]" : options.bind;
  if (live) {
    for (const std::string& line : live->OspEndpointLines()) std::cout << line << std::endl;
  }
  std::cout << "orcs-view: serving http://" << host << ":" << port << "/ (Ctrl-C to stop)" << std::endl;
  server.Serve();
  return cli::kExitOk;
}

}  // namespace
}  // namespace orcs::viewer

int main(int argc, char** argv) {
  return orcs::cli::RunProgram("orcs-view", orcs::viewer::ParseViewOptions(argc, argv), [](const auto& options) {
    return options.render ? orcs::viewer::RenderClip(options) : orcs::viewer::Serve(options);
  });
}
