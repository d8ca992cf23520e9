// What orcs-view was given: recordings, batch folders, evolve folders and gap reports, as items with ids the
// page asks for (r0, b0, e0, g0, ...). Ids stand for files; no route ever takes a path, so the server serves
// nothing but what it was given (docs/viewer-api.md). A folder may still be in the making (its command's
// progress.json says "running"): each look at it adds the recordings that have appeared since, and its answer
// carries the progress (docs/viewer.md, "Runs in progress"). Thread-safe: the server's threads share it.
#pragma once

#include <deque>
#include <filesystem>
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
  std::string id;      ///< "r0", "b0", "e0", "g0", "p0" (a robot run)
  std::string kind;    ///< "recording", "batch", "evolve", "gap" or "robot"
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

  /// A copy of the items now.
  std::vector<ViewItem> Items() const;
  /// The item with this id, or nullptr. Items are never removed or moved: the pointer stays valid.
  const ViewItem* Find(std::string_view id) const;

  /// {"items": [...]} for /api/session.
  nlohmann::json ItemsJson() const;
  /// The recording of a recording item, read on first use and kept, and read again when its file has changed (a
  /// robot run's grows while the robot moves: read up to its last complete frame). Throws InputError when the file is
  /// bad.
  std::shared_ptr<const evaluation::Recording> Recording(std::string_view id);
  /// /api/batch, /api/evolve, /api/gap answers; nullopt for an id of another kind. Each first adds the
  /// recordings that have appeared in the folder since, and carries "progress": its progress.json, or null.
  std::optional<nlohmann::json> BatchJson(std::string_view id);
  std::optional<nlohmann::json> EvolveJson(std::string_view id);
  std::optional<nlohmann::json> GapJson(std::string_view id);
  /// /api/robot: an orcs-robot --view folder — {"name", "run": its robot_run.json, "robot": the recording of the
  /// measured robot, "twin": the twin's (ids or null), "bytes": {"robot", "twin"} (each file's size, which grows
  /// while the robot moves), "progress"}.
  std::optional<nlohmann::json> RobotJson(std::string_view id);
  /// The recorded jobs of the batch folders whose progress.json names their broker batch, for the dashboard's
  /// links from a finished job to its replay: [{"batch": broker batch id, "job": job id, "recording": "r3"}].
  nlohmann::json ReplaysJson();

 private:
  void AddInput(const std::string& input);
  void AddFolder(const std::string& folder);
  /// Adds the children of a folder item not there yet (recordings, an evolve run's winner batch). With
  /// items_mutex_ held.
  void AddChildren(const ViewItem& item);
  /// Refreshes the item's children; the item, or nullptr when it is not of `kind`.
  const ViewItem* Refreshed(std::string_view id, std::string_view kind);
  std::string AddRecording(const std::string& path, const std::string& parent, const std::string& label);
  std::string AddItem(std::string kind, std::string label, std::string path, std::string parent);
  /// With items_mutex_ held.
  const ViewItem* FindLocked(std::string_view id) const;
  std::string RecordingIdOf(const std::string& path) const;
  std::vector<ViewItem> ChildrenOf(const std::string& parent) const;

  mutable std::mutex items_mutex_;  // guards items_, counters_, recording_ids_
  std::deque<ViewItem> items_;      ///< a deque: adding keeps pointers to the others valid
  std::map<std::string, int, std::less<>> counters_;
  std::map<std::string, std::string> recording_ids_;  ///< recording path → its id
  mutable std::mutex mutex_;  // guards cache_
  struct Cached {
    std::shared_ptr<const evaluation::Recording> recording;
    std::uintmax_t bytes = 0;                  // the file's size when read
    std::filesystem::file_time_type modified;  // and its modification time
  };
  std::map<std::string, Cached, std::less<>> cache_;
};

}  // namespace orcs::viewer
