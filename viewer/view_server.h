// orcs-view's HTTP server (docs/viewer-api.md): the page's files, the files-mode routes over a ViewCatalog, the
// live-mode routes over a LiveSession and the render routes over a RenderSink. Binds to loopback unless told
// otherwise, serves nothing but those routes, and bounds what a request may cost: bodies up to 1 MiB, patterns up
// to 1000 characters, reads time out, a fixed pool of threads.
//
// It answers only requests addressed to itself (docs/viewer-api.md, "Who may ask"): a Host that is not one of its
// own names and port (DNS rebinding) and an Origin that is not its own page (another site's page) are refused with
// 403 before any route runs; every answer forbids framing (clickjacking) and cross-origin embedding.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "viewer/broker_watch.h"
#include "viewer/live_session.h"
#include "viewer/render_sink.h"
#include "viewer/view_catalog.h"
#include "viewer/web_assets.h"

namespace orcs::viewer {

class HttpServer;  // httplib::Server, with its request handling reachable without a socket (Answer)

class ViewServer {
 public:
  /// Serves `assets` and, where given, a catalog (files mode), a live session, a render sink or a broker's
  /// status (the dashboard) (not owned).
  ViewServer(const WebAssets& assets, ViewCatalog* catalog, LiveSession* live, RenderSink* render,
             BrokerWatch* broker = nullptr);
  ~ViewServer();

  /// Binds `address`:`port` (0 = any free port) and returns the port. Throws InputError naming the address and
  /// port when it cannot bind ("port 8765 on 127.0.0.1 is in use or not allowed").
  int Bind(const std::string& address, int port);
  /// Also answers requests addressed to `name` (--allow-host: a DNS name of this machine, when bound to another
  /// interface). Before Bind().
  void AllowHost(const std::string& name);
  /// Why a request with these Host and Origin headers (nullopt = absent) is refused, "" when it is not.
  std::string Refusal(const std::optional<std::string>& host, const std::optional<std::string>& origin) const;
  /// Serves until Stop(). Blocks.
  void Serve();
  /// Makes Serve() return; safe from any thread or a signal-watching thread.
  void Stop();

  /// Answers `bytes` as one connection's worth of requests, exactly as Serve() answers a socket's — the same
  /// httplib request parsing, routes and handlers — and returns the bytes written back for each request read, in
  /// order. Handles at most `max_requests` keep-alive requests; stops when the bytes run out or the connection
  /// closes. For the fuzzer (tests/fuzz/view_request_fuzz.cc) and tests; needs no Bind(). Before Bind() the Host
  /// check compares names only (there is no port yet).
  std::vector<std::string> Answer(std::string_view bytes, int max_requests = 8);

  /// How long GET /api/live/frame waits for a newer frame (default 0.5 s).
  void SetLongPoll(std::chrono::milliseconds wait) { long_poll_ = wait; }

 private:
  void AddPageRoutes();
  void AddFilesRoutes();
  void AddLiveRoutes();
  void AddLiveValueRoutes();
  void AddRenderRoutes();
  void AddBrokerRoutes();

  const WebAssets& assets_;
  ViewCatalog* catalog_;
  LiveSession* live_;
  RenderSink* render_;
  BrokerWatch* broker_;
  std::unique_ptr<HttpServer> server_;
  std::chrono::milliseconds long_poll_{500};
  std::vector<std::string> host_names_{"127.0.0.1", "localhost", "[::1]"};  // lower case, IPv6 in brackets
  bool any_address_ = false;  // bound to 0.0.0.0 or ::: any address of this machine (an IP literal) is its name
  int port_ = 0;              // 0 before Bind (Answer): the port is not checked
};

}  // namespace orcs::viewer
