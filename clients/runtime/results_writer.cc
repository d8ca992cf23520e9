#include "clients/runtime/results_writer.h"

#include <filesystem>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/evaluation/recorder.h"
#include "proto/result_json.h"

namespace orcs::runtime {
namespace {

namespace fs = std::filesystem;

constexpr const char* kResults = "results.jsonl";
constexpr const char* kPartial = "results.jsonl.partial";
constexpr const char* kRecordings = "recordings";
constexpr const char* kRecordingExtension = ".orcsrec";  // docs/recording.md; what orcs-view looks for

// A job id as a file name: anything but letters, digits, '-', '_' and '.' becomes '_'.
std::string FileNameOf(const std::string& job_id) {
  std::string name = job_id;
  for (char& c : name) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                      c == '_' || c == '.';
    if (!safe) c = '_';
  }
  if (name.empty() || name.front() == '.') name.insert(0, "_");
  return name;
}

}  // namespace

PartialResults ReadPartialResults(const std::string& folder) {
  const fs::path path = fs::path(folder) / kPartial;
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    const bool complete = fs::is_regular_file(fs::path(folder) / kResults, error);
    throw InputError(folder, 0, complete ? "the batch is complete already (results.jsonl): nothing to resume"
                                         : "no interrupted batch here (no results.jsonl.partial)");
  }
  std::ifstream in(path, std::ios::binary);
  PartialResults partial;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const bool ended = !in.eof();  // the line had its newline: it was written whole
    try {
      partial.results.push_back(proto::ResultFromJson(nlohmann::json::parse(line)));
    } catch (const std::exception& problem) {
      if (!ended) break;  // cut short by the interruption: run that job again
      throw InputError(path.string(), number, std::string("not a result line: ") + problem.what());
    }
    if (!ended) {  // whole but for its newline: the job runs again rather than trust it
      partial.results.pop_back();
      break;
    }
    partial.bytes += line.size() + 1;
  }
  return partial;
}

ResultsWriter::ResultsWriter(std::string folder, Start start, std::uintmax_t kept_bytes) : folder_(std::move(folder)) {
  std::error_code error;
  fs::create_directories(fs::path(folder_) / "logs", error);
  if (error) throw InputError(folder_, 0, "cannot create the output folder: " + error.message());
  if (start == Start::kResume) {
    fs::resize_file(fs::path(folder_) / kPartial, kept_bytes, error);  // drops a line the interruption cut
    if (error) throw InputError((fs::path(folder_) / kPartial).string(), 0, "cannot be resumed: " + error.message());
    partial_.open(fs::path(folder_) / kPartial, std::ios::app);
    if (!partial_) throw InputError((fs::path(folder_) / kPartial).string(), 0, "cannot be written");
    return;
  }
  for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(folder_) / "logs", error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".csv") fs::remove(entry.path(), error);
  }
  // An earlier batch's recordings would show up beside this batch's jobs in orcs-view: remove them too. The folder
  // itself is made when the first recording arrives.
  for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(folder_) / kRecordings, error)) {
    if (entry.is_regular_file() && entry.path().extension() == kRecordingExtension) fs::remove(entry.path(), error);
  }
  partial_.open(fs::path(folder_) / kPartial, std::ios::trunc);
  if (!partial_) throw InputError((fs::path(folder_) / kPartial).string(), 0, "cannot be written");
}

std::string ResultsWriter::results_path() const {
  return (fs::path(folder_) / (finished_ ? kResults : kPartial)).string();
}

void ResultsWriter::Write(const v1::Result& result, const nlohmann::ordered_json& extra) {
  const nlohmann::ordered_json fields = proto::ResultToJson(result);
  nlohmann::ordered_json line;
  for (auto it = fields.begin(); it != fields.end(); ++it) {
    line[it.key()] = it.value();
    if (it.key() == "id") {
      for (auto e = extra.begin(); e != extra.end(); ++e) line[e.key()] = e.value();
    }
  }
  // The recording first, so that a line naming it never precedes the file.
  if (!result.recording().empty()) line["recording"] = WriteRecording(result);
  partial_ << line.dump() << '\n' << std::flush;
  if (!partial_) throw InputError(results_path(), 0, "writing failed");
  WriteLogs(result);
}

std::string ResultsWriter::WriteRecording(const v1::Result& result) {
  const fs::path relative = fs::path(kRecordings) / (FileNameOf(result.job_id()) + kRecordingExtension);
  std::error_code error;
  fs::create_directories(fs::path(folder_) / kRecordings, error);
  if (error) throw InputError((fs::path(folder_) / kRecordings).string(), 0, "cannot be created: " + error.message());
  evaluation::WriteRecording((fs::path(folder_) / relative).string(), result.recording());
  return relative.string();
}

void ResultsWriter::WriteLogs(const v1::Result& result) {
  const std::string base = FileNameOf(result.job_id());
  for (const v1::LogFile& log : result.logs()) {
    std::string name = base + ".csv";
    if (result.parameter_sets_size() > 1) {
      const std::string set = fs::path(log.name()).stem().string();  // "set-1"
      name = base + "." + FileNameOf(set) + ".csv";
    }
    AtomicFile file((fs::path(folder_) / "logs" / name).string());
    file.stream() << log.csv();
    file.Commit();
  }
}

void ResultsWriter::Finish() {
  partial_.close();
  std::error_code error;
  fs::rename(fs::path(folder_) / kPartial, fs::path(folder_) / kResults, error);
  if (error) throw InputError(results_path(), 0, "cannot be renamed: " + error.message());
  finished_ = true;
}

}  // namespace orcs::runtime
