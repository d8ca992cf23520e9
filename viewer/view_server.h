// orcs-view's HTTP server (docs/viewer-api.md): the page's files, the files-mode routes over a ViewCatalog, the
// live-mode routes over a LiveSession and the render routes over a RenderSink. Binds to loopback unless told
// otherwise, serves nothing but those routes, and bounds what a request may cost: bodies up to 1 MiB, patterns up
// to 1000 characters, reads time out, a fixed pool of threads.
#pragma once

#include <memory>
#include <string>

#include "viewer/live_session.h"
#include "viewer/render_sink.h"
#include "viewer/view_catalog.h"
#include "viewer/web_assets.h"

namespace httplib {
class Server;
}

namespace orcs::viewer {

class ViewServer {
 public:
  /// Serves `assets` and, where given, a catalog (files mode), a live session or a render sink (not owned).
  ViewServer(const WebAssets& assets, ViewCatalog* catalog, LiveSession* live, RenderSink* render);
  ~ViewServer();

  /// Binds `address`:`port` (0 = any free port) and returns the port. Throws InputError naming the address and
  /// port when it cannot bind ("port 8765 on 127.0.0.1 is in use or not allowed").
  int Bind(const std::string& address, int port);
  /// Serves until Stop(). Blocks.
  void Serve();
  /// Makes Serve() return; safe from any thread or a signal-watching thread.
  void Stop();

 private:
  void AddPageRoutes();
  void AddFilesRoutes();
  void AddLiveRoutes();
  void AddRenderRoutes();

  const WebAssets& assets_;
  ViewCatalog* catalog_;
  LiveSession* live_;
  RenderSink* render_;
  std::unique_ptr<httplib::Server> server_;
};

}  // namespace orcs::viewer
