// Logs selected repository values once per step to a CSV file — the native trace format of orcs, shared by
// simulated and measured runs (docs/formats.md):
//
//   # <comment lines: program, environment, seed, ...>
//   # columns: time,/Sim/SecondSphere/Position.x,/Sim/SecondSphere/Position.y,...
//   0.01,0.5,0.4995,...
//
// A vector3d value is three columns (path.x, .y, .z), a quaternion four (.w .x .y .z), a colour four
// (.r .g .b .a); a bool is 0 or 1. Numbers print in shortest round-trip form. The file is written under a
// temporary name and appears under its own name only at Finish().
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "model/core/atomic_file.h"
#include "model/core/variable_repository.h"

namespace orcs {

class ValueLogger {
 public:
  /// Selects every value whose path matches one of `regular_expressions`, in repository order, each once.
  /// Throws InputError when an expression is invalid or matches nothing (naming it).
  ValueLogger(const VariableRepository& repository, const std::vector<std::string>& regular_expressions);

  /// Column names: "time" first, then one per logged component.
  std::vector<std::string> column_names() const;

  /// Starts writing to `path`: the comment lines (each prefixed "# "), then the column line. `max_bytes` and `why`
  /// bound the file as OpenInMemory's bound the memory.
  void Open(const std::string& path, const std::vector<std::string>& comments,
            std::size_t max_bytes = std::numeric_limits<std::size_t>::max(), std::string why = "");
  /// Starts writing to memory instead of a file (a worker returns the log in its result): see TakeText(). The log
  /// holds at most `max_bytes`: the row that would pass the bound is not written, a comment line
  /// "# log truncated at time T s: <why>" ends the log instead, and later samples are dropped (see truncated()).
  /// `why` should name the bound and the fix.
  void OpenInMemory(const std::vector<std::string>& comments,
                    std::size_t max_bytes = std::numeric_limits<std::size_t>::max(), std::string why = "");
  /// What was written to memory since OpenInMemory, moved out (the logger's memory is then empty).
  std::string TakeText();
  /// Whether the log reached its max_bytes and dropped samples.
  bool truncated() const { return truncated_; }
  /// Bytes written since Open or OpenInMemory (comment lines included).
  std::size_t bytes() const { return written_; }
  /// Appends one row with the current values; `time` in seconds. Only after Open().
  void Sample(double time);
  /// Completes the file (rename onto its name). Throws InputError when writing failed.
  void Finish();

 private:
  const VariableRepository& repository_;
  std::vector<int> ids_;
  void WriteHeader(const std::vector<std::string>& comments);

  std::unique_ptr<AtomicFile> file_;
  std::ostringstream memory_;
  std::ostream* out_ = nullptr;  // file_'s stream or memory_
  std::size_t max_bytes_ = std::numeric_limits<std::size_t>::max();  // bound on the log
  std::size_t written_ = 0;      // bytes written since opening
  bool truncated_ = false;       // the bound was reached: samples are dropped
  std::string why_truncated_;    // the truncation line's reason
  std::string row_;  // reused buffer, so sampling does not allocate once warm
};

}  // namespace orcs
