// Where orcs-view --render's frames go: the page, opened by headless chromium in render mode, posts each drawn
// frame as PNG (POST /api/render/frame?index=K), then POST /api/render/done. The sink writes the frames into a
// folder and wakes whoever waits for the end.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>

namespace orcs::viewer {

class RenderSink {
 public:
  /// Frames go to `folder` (existing) as frame-00000.png ...; at most `max_frames` are accepted.
  RenderSink(std::string folder, int max_frames);

  /// Stores frame `index` (PNG bytes). Returns false — the server answers 400 — for an index outside
  /// 0…max_frames−1 or bytes that are not a PNG.
  bool AddFrame(int index, const std::string& png);
  /// The page is done (`error` = "" on success, else what went wrong in the page).
  void Done(const std::string& error);
  /// Waits until Done() or `timeout`; true when done in time.
  bool WaitDone(std::chrono::seconds timeout);

  int frames() const;                ///< frames stored so far
  std::string error() const;         ///< the page's error, "" = none
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
  int max_frames_;
  mutable std::mutex mutex_;
  std::condition_variable done_changed_;
  int frames_ = 0;
  bool done_ = false;
  std::string error_;
};

}  // namespace orcs::viewer
