#include "viewer/view_options.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>

#include "net/cli_style.h"

#ifndef ORCS_WEB_DIR
#define ORCS_WEB_DIR "viewer/web"
#endif

namespace orcs::viewer {

ParsedViewOptions ParseViewOptions(int argc, const char* const* argv) {
  ParsedViewOptions parsed;
  ViewOptions& o = parsed.options;
  o.web_dir = ORCS_WEB_DIR;
  RenderOptions& r = o.render_options;
  LiveOptions& l = o.live_options;
  CLI::App app("orcs-view: see what the robot does. Serves recordings (*.orcsrec), batch, evolve and gap folders, or "
               "a live simulation (--live), to a browser; --render draws a still or a clip.",
               "orcs-view");
  app.add_option("inputs", o.inputs, "recordings and folders (batch, evolve, gap) to open")->check(CLI::ExistingPath);
  app.add_option("--port", o.port, "port to serve on (0 = any free port)")->check(CLI::Range(0, 65535));
  app.add_option("--bind", o.bind, "interface to listen on (default 127.0.0.1: this machine only)");
  app.add_option("--allow-host", o.allow_hosts,
                 "also answer requests addressed to this name (a DNS name of this machine; docs/viewer.md)")
      ->check([](const std::string& name) -> std::string {
        const bool plain = !name.empty() && name.size() <= 253 && std::all_of(name.begin(), name.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_';
        });
        return plain ? "" : "expected a host name (letters, digits, '.', '-', '_')";
      });
  app.add_option("--web-dir", o.web_dir, "the page's folder, holding files.txt")->check(CLI::ExistingDirectory);
  CLI::Option* live = app.add_flag("--live", o.live, "run a simulation in the server: the original's GUI");
  app.add_option("--env", l.environment, "with --live: ORCS XML environment (-env also accepted)")
      ->check(CLI::ExistingFile)->needs(live);
  app.add_option("--ival", l.initial_value_files, "with --live: value file loaded before the world is built")
      ->check(CLI::ExistingFile)->needs(live);
  app.add_option("--val", l.value_files, "with --live: value file loaded after the world is built")
      ->check(CLI::ExistingFile)->needs(live);
  app.add_flag("--strict", l.strict, "with --live: refuse a value file naming a path orcs lacks")->needs(live);
  app.add_option("--seed", l.seed, "with --live: seed of every reset")->check(cli::Seed())->needs(live);
  app.add_option("--files", l.files_dir, "with --live: folder for saved value files and logs")->needs(live);
  app.add_flag("--run", l.start_running, "with --live: start running instead of paused")->needs(live);
  std::size_t log_max_mib = l.log_max_bytes >> 20;
  app.add_option("--log-max-mib", log_max_mib, "with --live: a log stops at this many MiB (default 64)")
      ->check(CLI::Range(1, 65536))->needs(live);
  app.add_option("--log-max-seconds", l.log_max_seconds,
                 "with --live: a log stops after this many seconds (default 600)")
      ->check(CLI::Range(1.0, 86400.0))->needs(live);
  app.add_option("--control-timeout", l.control_timeout,
                 "with --live: a page silent this many seconds loses control, and its log stops (default 10)")
      ->check(CLI::Range(1.0, 3600.0))->needs(live);
  LiveOspOptions& osp = l.osp;
  CLI::Option* osp_flag = app.add_flag("--osp", osp.enabled,
                                       "with --live: OSP clients step and reset the simulation (orcs-osp -gui); the "
                                       "page watches, sets values and logs")
                              ->needs(live);
  app.add_option("--osp-port", osp.port, "with --osp: the OSP server port (default 45454; 0 = any)")
      ->check(CLI::Range(0, 65535))->needs(osp_flag);
  app.add_option("--odcp-port", osp.odcp_port, "with --osp: the ODCP servers' base port (default 45453; 0 = any)")
      ->check(CLI::Range(0, 65535))->needs(osp_flag);
  app.add_option("--osp-bind", osp.bind_address, "with --osp: the OSP and ODCP sockets' interface (default 127.0.0.1)")
      ->needs(osp_flag);
  app.add_option("--client-timeout", osp.client_timeout_seconds,
                 "with --osp: seconds of silence after which an OSP client loses its agents (default 10)")
      ->check(cli::NumberIn(0.001, 1e6))->needs(osp_flag);
  app.add_option("--record", osp.record, "with --osp: folder for one recording per episode (reset to reset)")
      ->needs(osp_flag);
  CLI::Option* broker = app.add_option("--broker", o.broker,
                                       "show this broker's dashboard: workers, batches, throughput (its client "
                                       "endpoint, e.g. tcp://127.0.0.1:5555)")
                            ->check(cli::Endpoint());
  app.add_option("--curve-keys", o.curve_keys,
                 "with --broker: folder of the client keys to ask with (docs/security.md)")
      ->needs(broker);
  CLI::Option* render = app.add_option("--render", r.run, "draw this recording (or a folder's first) to --out")
                            ->check(CLI::ExistingPath);
  app.add_option("--out", r.out, "with --render: .png (a still), .gif, .mp4 or .webm (a clip)")->needs(render);
  app.add_option("--from", r.from, "with --render: first second of a clip")->check(CLI::NonNegativeNumber)->needs(render);
  app.add_option("--to", r.to, "with --render: last second of a clip (default: the end)")
      ->check(CLI::NonNegativeNumber)->needs(render);
  app.add_option("--at", r.at, "with --render: the still's second (default: the middle)")
      ->check(CLI::NonNegativeNumber)->needs(render);
  app.add_option("--fps", r.fps, "with --render: clip frames per second")->check(CLI::Range(1.0, 60.0))->needs(render);
  app.add_option("--width", r.width, "with --render: pixels")->check(CLI::Range(64, 3840))->needs(render);
  app.add_option("--height", r.height, "with --render: pixels")->check(CLI::Range(64, 2160))->needs(render);
  app.add_option("--chromium", r.chromium, "with --render: the headless browser that draws")->needs(render);

  const auto validate = [&] {
    o.render = !r.run.empty();
    if (o.render && r.out.empty()) throw CLI::ValidationError("--render", "needs --out FILE (.png, .gif, .mp4, .webm)");
    if (o.render && !o.inputs.empty()) throw CLI::ValidationError("--render", "takes one run; give it no other inputs");
    if (o.render && o.live) throw CLI::ValidationError("--render", "draws recordings, not --live");
    if (o.live && !o.inputs.empty()) throw CLI::ValidationError("--live", "serves a simulation; give it no recordings");
    if (!o.broker.empty() && (o.live || o.render)) {
      throw CLI::ValidationError("--broker", "shows a dashboard beside recordings and folders, not with --live or --render");
    }
    if (!o.live && !o.render && o.inputs.empty() && o.broker.empty()) {
      throw CLI::ValidationError("orcs-view",
                                 "give recordings or folders to open, --broker ENDPOINT, --live, or --render RUN --out FILE");
    }
    if (r.to >= 0 && r.to <= r.from) throw CLI::ValidationError("--to", "must be after --from");
    if (osp.enabled && l.start_running) {
      throw CLI::ValidationError("--run", "not with --osp: the OSP clients step the simulation");
    }
    l.log_max_bytes = log_max_mib << 20;
  };
  parsed.exit_code = cli::ParseArguments(app, argc, argv, {"env", "ival", "val"}, validate);
  return parsed;
}

}  // namespace orcs::viewer
