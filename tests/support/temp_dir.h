// A fresh temporary directory for one test: made when the test starts, removed with everything in it when
// the test ends. Tests that write files (value files, logs, environments) work inside it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace orcs::test_support {

/// A new, empty directory under the system temporary directory, named after the running GoogleTest test
/// (suite, name, process id and a counter, so that no two are the same). The destructor removes it.
/// Make it a member of the test fixture (or a local of the test): it reads the current test's name.
class TempDir {
 public:
  /// Makes the directory; throws std::runtime_error when it cannot.
  TempDir();
  /// Removes the directory and everything in it (errors ignored).
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// The directory.
  const std::filesystem::path& path() const { return path_; }

  /// The full path of `relative_name` in the directory (an absolute name is returned as it is).
  std::string PathOf(const std::string& relative_name) const;

  /// Writes `contents` to `relative_name` (folders created as needed) and returns its full path.
  /// Throws std::runtime_error when the file cannot be written.
  std::string Write(const std::string& relative_name, const std::string& contents) const;

  /// The whole contents of `relative_name_or_absolute_path`; an empty string when it cannot be read.
  std::string Read(const std::string& relative_name_or_absolute_path) const;

  /// The names of the entries directly in the directory, sorted.
  std::vector<std::string> FileNames() const;

 private:
  std::filesystem::path path_;
};

}  // namespace orcs::test_support
