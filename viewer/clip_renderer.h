// orcs-view --render: a still or a clip of a recording, drawn by the page itself. The server is started on
// loopback, headless chromium opens the page in render mode, the page draws the frames one by one and posts them
// (RenderSink), and ffmpeg turns them into a GIF, MP4 or WebM; a still is the one frame's PNG. Nothing is drawn
// twice: what the README shows is what a browser shows.
#pragma once

#include <string>

#include "viewer/view_options.h"

namespace orcs::viewer {

/// Renders `options.render_options`. Returns the exit code: 0 done, 1 the browser or encoder failed (one line
/// printed), 2 bad input (thrown as InputError by what it calls: a bad recording, an unknown extension).
int RenderClip(const ViewOptions& options);

}  // namespace orcs::viewer
