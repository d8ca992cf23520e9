// An output file that appears under its name only when complete: written to "<name>.tmp.<pid>.<n>" and renamed on
// Commit(). Destroyed without Commit() (an error, an exception), the temporary file is removed, so a half-written
// file never looks finished (docs/architecture.md, "Errors and bad input").
#pragma once

#include <fstream>
#include <string>

namespace orcs {

class AtomicFile {
 public:
  /// Opens the temporary file; throws InputError naming `path` when it cannot be created.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return stream_; }
  /// Flushes, closes and renames onto the final path; throws InputError when writing failed.
  void Commit();

 private:
  std::string path_;
  std::string temporary_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

}  // namespace orcs
