// DIR/progress.json: what a long command (orcs-batch run, submit, sweep, regress and evolve, orcs-gap) is doing
// now, for orcs-view's page, which follows a run in progress from its folder (docs/viewer.md, "Runs in progress").
// The file is replaced atomically, at most once a second while the command runs and once more when it ends, so a
// reader never sees half a file and the command never waits for a reader:
//   {"format": "orcs-progress", "version": 1, "command": "evolve", "state": "running", "updated_unix": 1795000000.2,
//    "pid": 4242, ...the command's fields: "done", "total", "jobs_per_second", "eta_seconds", "generation", ...}
// A command that ends by an exception leaves state "failed"; one that dies leaves "running" with an old
// updated_unix, which the page reports as stale. A write that fails is said once on stderr and does not stop the
// command: the file is for watching, the results are what matter.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

namespace orcs::runtime {

/// The file's name within the output folder.
inline constexpr const char* kProgressFile = "progress.json";

class ProgressFile {
 public:
  using Clock = std::chrono::steady_clock;

  /// Follows `command` ("batch", "sweep", "regress", "evolve", "gap") in `folder`, which must exist; writes the
  /// file at once (at `now`) with state "running". An empty folder makes a ProgressFile that writes nothing.
  ProgressFile(std::string folder, std::string command, Clock::time_point now = Clock::now());
  /// Writes state "failed" unless Finish() was called: the command ended by an exception.
  ~ProgressFile();
  ProgressFile(const ProgressFile&) = delete;
  ProgressFile& operator=(const ProgressFile&) = delete;

  /// Sets (or with null removes) one of the command's fields; written by the next Update().
  void Set(const std::string& key, nlohmann::json value);
  /// Sets every field of `fields` (an object).
  void Merge(const nlohmann::json& fields);
  /// Whether a second has passed since the last write: Update() would write.
  bool Due(Clock::time_point now) const { return now - last_write_ >= std::chrono::seconds(1); }
  /// Writes the file when Due(), or now when `force`.
  void Update(Clock::time_point now, bool force = false);
  /// The final state: "finished" or "interrupted". Writes at once.
  void Finish(const std::string& state);

  /// What the file holds (or would hold): for tests.
  const nlohmann::json& fields() const { return fields_; }

 private:
  void Write(Clock::time_point now);

  std::string path_;             ///< folder/progress.json; "" = write nothing
  nlohmann::json fields_;        ///< everything the file holds
  Clock::time_point last_write_; ///< when Write() last ran
  bool finished_ = false;        ///< Finish() was called
  bool warned_ = false;          ///< a write failed and stderr was told
};

}  // namespace orcs::runtime
