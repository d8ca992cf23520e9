// What orcs-view was given: recordings, batch folders, evolve folders and gap reports, as items with ids the
// page asks for (r0, b0, e0, g0, ...). Ids stand for files; no route ever takes a path, so the server serves
// nothing but what it was given (docs/viewer-api.md).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/evaluation/recording_reader.h"

namespace orcs::viewer {

struct ViewItem {
  std::string id;      ///< "r0", "b0", "e0", "g0"
  std::string kind;    ///< "recording", "batch", "evolve" or "gap"
  std::string label;   ///< what the page shows
  std::string path;    ///< the file or folder
  std::string parent;  ///< the batch, evolve or gap item a recording belongs to, "" = given directly
};

class ViewCatalog {
 public:
  /// Resolves each input. A file must be a recording (read whole now, so a bad one is reported before serving);
  /// a folder a batch (results.jsonl), an evolve run (fitness.csv), a gap report (report.json) or a folder of
  /// recordings. Throws InputError naming the path: missing, unreadable, not a recording, nothing viewable.
  explicit ViewCatalog(const std::vector<std::string>& inputs);

  const std::vector<ViewItem>& items() const { return items_; }
  /// The item with this id, or nullptr.
  const ViewItem* Find(std::string_view id) const;

  /// {"items": [...]} for /api/session.
  nlohmann::json ItemsJson() const;
  /// The recording of a recording item, read on first use and kept. Throws InputError when the file is bad.
  std::shared_ptr<const evaluation::Recording> Recording(std::string_view id);
  /// /api/batch, /api/evolve, /api/gap answers; nullopt for an id of another kind.
  std::optional<nlohmann::json> BatchJson(std::string_view id) const;
  std::optional<nlohmann::json> EvolveJson(std::string_view id) const;
  std::optional<nlohmann::json> GapJson(std::string_view id) const;

 private:
  void AddInput(const std::string& input);
  void AddFolder(const std::string& folder);
  std::string AddRecording(const std::string& path, const std::string& parent, const std::string& label);
  std::string AddItem(std::string kind, std::string label, std::string path, std::string parent);
  std::string RecordingIdOf(const std::string& path) const;

  std::vector<ViewItem> items_;
  std::map<std::string, int, std::less<>> counters_;
  mutable std::mutex mutex_;  // guards cache_
  std::map<std::string, std::shared_ptr<const evaluation::Recording>, std::less<>> cache_;
};

}  // namespace orcs::viewer
