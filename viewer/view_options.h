// The options of orcs-view (docs/viewer.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "viewer/live_session.h"

namespace orcs::viewer {

/// What orcs-view --render makes.
struct RenderOptions {
  std::string run;         ///< --render RUN: a recording, or a folder whose first recording is drawn
  std::string out;         ///< --out FILE: .png (a still), .gif, .mp4 or .webm (a clip)
  double from = 0.0;       ///< --from: first simulated second of a clip
  double to = -1.0;        ///< --to: last simulated second of a clip, −1 = the end
  double at = -1.0;        ///< --at: the still's simulated second, −1 = the middle of the run
  double fps = 25.0;       ///< --fps: clip frames per (played) second
  int width = 960;         ///< --width: pixels
  int height = 540;        ///< --height: pixels
  std::string chromium = "chromium";  ///< --chromium: the browser that draws the frames
};

struct ViewOptions {
  std::vector<std::string> inputs;  ///< recordings and folders to serve
  int port = 8765;                  ///< --port: 0 = any free port
  std::string bind = "127.0.0.1";   ///< --bind: interface to listen on
  std::vector<std::string> allow_hosts;  ///< --allow-host: more names requests may be addressed to
  std::string web_dir;              ///< --web-dir: the page's folder (holds files.txt)
  bool live = false;                ///< --live: serve a live simulation
  LiveOptions live_options;         ///< its world
  std::string broker;               ///< --broker ENDPOINT: show that broker's dashboard ("" = none)
  std::string curve_keys;           ///< --curve-keys DIR: the client keys the dashboard asks with ("" = plain TCP)
  bool render = false;              ///< --render given
  RenderOptions render_options;     ///< what to render
};

struct ParsedViewOptions {
  ViewOptions options;
  int exit_code = -1;  ///< >= 0: exit now (help printed, or bad options reported)
};

ParsedViewOptions ParseViewOptions(int argc, const char* const* argv);

}  // namespace orcs::viewer
