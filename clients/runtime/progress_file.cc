#include "clients/runtime/progress_file.h"

#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "model/core/atomic_file.h"
#include "model/core/error.h"

namespace orcs::runtime {
namespace {

double UnixSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

ProgressFile::ProgressFile(std::string folder, std::string command, Clock::time_point now)
    : path_(folder.empty() ? "" : (std::filesystem::path(folder) / kProgressFile).string()),
      fields_({{"format", "orcs-progress"},
               {"version", 1},
               {"command", std::move(command)},
               {"state", "running"},
               {"pid", static_cast<long long>(::getpid())}}) {
  Write(now);
}

ProgressFile::~ProgressFile() {
  if (finished_) return;
  fields_["state"] = "failed";  // the command ended by an exception
  Write(Clock::now());
}

void ProgressFile::Set(const std::string& key, nlohmann::json value) {
  if (value.is_null()) {
    fields_.erase(key);
  } else {
    fields_[key] = std::move(value);
  }
}

void ProgressFile::Merge(const nlohmann::json& fields) {
  for (const auto& [key, value] : fields.items()) Set(key, value);
}

void ProgressFile::Update(Clock::time_point now, bool force) {
  if (!force && !Due(now)) return;
  Write(now);
}

void ProgressFile::Finish(const std::string& state) {
  fields_["state"] = state;
  finished_ = true;
  Write(Clock::now());
}

void ProgressFile::Write(Clock::time_point now) {
  last_write_ = now;
  if (path_.empty()) return;
  fields_["updated_unix"] = UnixSeconds();
  try {
    AtomicFile file(path_);
    file.stream() << fields_.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    file.Commit();
  } catch (const InputError& error) {
    // The progress is for watching: a full disk or a removed folder must not stop the run that makes results.
    if (!warned_) std::cerr << "orcs: " << error.what() << " (the progress for orcs-view); the run goes on\n";
    warned_ = true;
  }
}

}  // namespace orcs::runtime
