#include "viewer/render_sink.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace orcs::viewer {

RenderSink::RenderSink(std::string folder, int max_frames) : folder_(std::move(folder)), max_frames_(max_frames) {}

bool RenderSink::AddFrame(int index, const std::string& png) {
  static constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
  if (index < 0 || index >= max_frames_ || png.compare(0, 8, kPngSignature, 8) != 0) return false;
  char name[32];
  std::snprintf(name, sizeof name, "frame-%05d.png", index);
  std::ofstream out(std::filesystem::path(folder_) / name, std::ios::binary);
  out.write(png.data(), static_cast<std::streamsize>(png.size()));
  if (!out) return false;
  std::lock_guard lock(mutex_);
  ++frames_;
  return true;
}

void RenderSink::Done(const std::string& error) {
  std::lock_guard lock(mutex_);
  done_ = true;
  error_ = error;
  done_changed_.notify_all();
}

bool RenderSink::WaitDone(std::chrono::seconds timeout) {
  std::unique_lock lock(mutex_);
  return done_changed_.wait_for(lock, timeout, [this] { return done_; });
}

int RenderSink::frames() const {
  std::lock_guard lock(mutex_);
  return frames_;
}

std::string RenderSink::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

}  // namespace orcs::viewer
