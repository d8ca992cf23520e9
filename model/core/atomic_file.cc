#include "model/core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>

#include "model/core/error.h"

namespace orcs {

namespace {
// Makes temporary names unique within the process too (two files for one path, one after the other).
std::string TemporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}
}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temporary_path_(TemporaryName(path_)) {
  stream_.open(temporary_path_, std::ios::out | std::ios::trunc);
  if (!stream_) throw InputError(path_, 0, "cannot create the file");
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  stream_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

void AtomicFile::Commit() {
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
    throw InputError(path_, 0, "cannot write the file");
  }
  committed_ = true;
}

}  // namespace orcs
