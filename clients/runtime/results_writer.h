// The output folder of a batch (docs/batch.md): DIR/results.jsonl, one JSON object per job in arrival order,
// DIR/logs/JOB.csv (JOB.set-K.csv when a job has several parameter sets) for the logged values, and
// DIR/recordings/JOB.orcsrec for the jobs that were recorded (docs/recording.md), each written atomically.
//
// Lines go to DIR/results.jsonl.partial as results arrive, flushed each time, so an interrupted batch keeps what
// it has; Finish() renames it to results.jsonl, so a results.jsonl is always a complete batch.
#pragma once

#include <fstream>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "orcs/v1/result.pb.h"

namespace orcs::runtime {

/// What an interrupted batch left in DIR/results.jsonl.partial.
struct PartialResults {
  std::vector<v1::Result> results;  ///< one per complete line, in the file's order (logs and recordings not read)
  std::uintmax_t bytes = 0;         ///< the length of the complete lines: a line cut by the interruption is dropped
};

/// Reads DIR/results.jsonl.partial for `--resume`. Throws InputError naming the file and line for a line that is
/// not a result (but for a last line without its newline: the one an interrupted write cut short), and naming
/// the folder when there is no partial file.
PartialResults ReadPartialResults(const std::string& folder);

class ResultsWriter {
 public:
  /// Whether the folder starts a new batch or goes on with an interrupted one.
  enum class Start {
    kNew,     ///< CSV logs and recordings left by an earlier batch are removed; the partial file starts empty
    kResume,  ///< everything stays; lines are appended after the partial file's first `kept_bytes`
  };

  /// Creates DIR and DIR/logs (with kNew, CSV files left there by an earlier batch are removed; so are recordings
  /// left in DIR/recordings). Throws InputError naming the folder when it cannot be created or written.
  explicit ResultsWriter(std::string folder, Start start = Start::kNew, std::uintmax_t kept_bytes = 0);

  /// Appends the result's line (worker::ResultToJson with `extra`'s members added after "id", and
  /// "recording": "recordings/JOB.orcsrec" when it carries one) and writes its logs and its recording. Throws
  /// InputError when a file cannot be written.
  void Write(const v1::Result& result, const nlohmann::ordered_json& extra);

  /// Renames results.jsonl.partial to results.jsonl.
  void Finish();

  const std::string& folder() const { return folder_; }
  /// The path results end up in (results.jsonl), or the partial file's before Finish().
  std::string results_path() const;

 private:
  void WriteLogs(const v1::Result& result);
  /// Writes the result's recording; returns its path relative to the folder.
  std::string WriteRecording(const v1::Result& result);

  std::string folder_;
  std::ofstream partial_;
  bool finished_ = false;
};

}  // namespace orcs::runtime
