#include "viewer/view_catalog.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/core/error.h"
#include "model/core/json_node.h"

namespace orcs::viewer {
namespace {

namespace fs = std::filesystem;

constexpr std::uintmax_t kMaxTableBytes = 256u << 20;  // results.jsonl, fitness.csv, report.json
constexpr const char* kRecordingExtension = ".orcsrec";
constexpr const char* kProgressFile = "progress.json";  // clients/runtime/progress_file.h

bool IsFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

// A bounded text file (a table the page shows); "" when it is missing.
std::string ReadTable(const fs::path& path) {
  if (!IsFile(path)) return "";
  std::error_code error;
  if (fs::file_size(path, error) > kMaxTableBytes) {
    throw InputError(path.string(), 0, "larger than " + std::to_string(kMaxTableBytes >> 20) + " MiB");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Recordings directly in `folder`, sorted by name.
std::vector<fs::path> RecordingsIn(const fs::path& folder) {
  std::vector<fs::path> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (entry.path().extension() == kRecordingExtension && IsFile(entry.path())) found.push_back(entry.path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

// The folder's progress.json (written by the command making it), or null when there is none or it is not one.
nlohmann::json ProgressOf(const fs::path& folder) {
  try {
    const std::string text = ReadTable(folder / kProgressFile);
    if (text.empty()) return nullptr;
    nlohmann::json progress = nlohmann::json::parse(text);
    return progress.is_object() && progress.value("format", "") == "orcs-progress" ? progress : nlohmann::json(nullptr);
  } catch (const std::exception&) {
    return nullptr;  // not ours, or unreadable: the page shows no progress rather than an error
  }
}

nlohmann::json NumberOrNull(const std::string& text) {
  if (text.empty()) return nullptr;
  try {
    std::size_t used = 0;
    const double number = std::stod(text, &used);
    return used == text.size() ? nlohmann::json(number) : nlohmann::json(nullptr);
  } catch (const std::exception&) {
    return nullptr;
  }
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// What a folder holds by its files: "evolve", "gap", "batch", or "" (a folder of recordings). A run that has not
// written its tables yet is known by its progress.json's command.
std::string FolderKind(const fs::path& root) {
  if (IsFile(root / "fitness.csv")) return "evolve";
  if (IsFile(root / "report.json")) return "gap";
  if (IsFile(root / "robot_run.json")) return "robot";
  if (IsFile(root / "results.jsonl") || IsFile(root / "results.jsonl.partial")) return "batch";
  const nlohmann::json progress = ProgressOf(root);
  const std::string command = progress.is_object() ? progress.value("command", "") : "";
  if (command == "evolve" || command == "gap") return command;
  if (command == "run" || command == "submit" || command == "sweep" || command == "regress") return "batch";
  return "";
}

}  // namespace

ViewCatalog::ViewCatalog(const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) AddInput(input);
  if (items_.empty()) throw InputError("orcs-view", 0, "nothing to show: give recordings (*.orcsrec) or folders");
}

void ViewCatalog::AddInput(const std::string& input) {
  std::error_code error;
  if (!fs::exists(input, error)) throw InputError(input, 0, "no such file or folder");
  if (fs::is_directory(input, error)) return AddFolder(input);
  if (!IsFile(input)) throw InputError(input, 0, "not a regular file");
  // Read whole now: a foreign, truncated or newer file is reported before the server starts.
  std::shared_ptr<const evaluation::Recording> recording =
      std::make_shared<evaluation::Recording>(evaluation::ReadRecording(input));
  std::string id;
  {
    std::lock_guard lock(items_mutex_);
    id = AddRecording(input, "", fs::path(input).filename().string());
  }
  std::error_code ignored;
  std::lock_guard lock(mutex_);
  cache_.emplace(id, Cached{std::move(recording), fs::file_size(input, ignored), fs::last_write_time(input, ignored)});
}

void ViewCatalog::AddFolder(const std::string& folder) {
  const fs::path root(folder);
  const std::string name = root.filename().empty() ? root.parent_path().filename().string() : root.filename().string();
  std::lock_guard lock(items_mutex_);
  const std::size_t before = items_.size();
  const std::string kind = FolderKind(root);
  if (!kind.empty()) {
    AddChildren(*FindLocked(AddItem(kind, name, folder, "")));
  } else {
    for (const fs::path& file : RecordingsIn(root)) AddRecording(file.string(), "", file.filename().string());
  }
  if (items_.size() == before) {
    throw InputError(folder, 0,
                     "nothing viewable: expected recordings (*.orcsrec), a batch (results.jsonl), an evolve run "
                     "(fitness.csv), a gap report (report.json), a robot run (robot_run.json) or a run in progress "
                     "(progress.json)");
  }
}

void ViewCatalog::AddChildren(const ViewItem& item) {
  const fs::path root(item.path);
  const auto add_new = [this](const fs::path& folder, const std::string& parent) {
    for (const fs::path& file : RecordingsIn(folder)) {
      if (recording_ids_.count(file.string()) == 0) AddRecording(file.string(), parent, file.stem().string());
    }
  };
  if (item.kind == "evolve") {
    std::string best;
    for (const ViewItem& child : items_) {
      if (child.parent == item.id && child.kind == "batch") best = child.id;
    }
    if (best.empty() && IsFile(root / "best" / "results.jsonl")) {
      best = AddItem("batch", item.label + " / winner and validation", (root / "best").string(), item.id);
    }
    if (!best.empty()) add_new(root / "best" / "recordings", best);
  } else if (item.kind == "gap") {
    add_new(root / "replays", item.id);
  } else if (item.kind == "batch") {
    add_new(root / "recordings", item.id);
  } else if (item.kind == "robot") {
    add_new(root, item.id);  // robot.orcsrec, twin.orcsrec: they appear at the run's first flush
  }
}

const ViewItem* ViewCatalog::Refreshed(std::string_view id, std::string_view kind) {
  std::lock_guard lock(items_mutex_);
  const ViewItem* item = FindLocked(id);
  if (item == nullptr || item->kind != kind) return nullptr;
  AddChildren(*item);
  return item;
}

std::string ViewCatalog::AddItem(std::string kind, std::string label, std::string path, std::string parent) {
  const char prefix = kind == "recording" ? 'r' : kind == "robot" ? 'p' : kind[0];
  std::string id = prefix + std::to_string(counters_[std::string(1, prefix)]++);
  items_.push_back({id, std::move(kind), std::move(label), std::move(path), std::move(parent)});
  return id;
}

std::string ViewCatalog::AddRecording(const std::string& path, const std::string& parent, const std::string& label) {
  std::string id = AddItem("recording", label, path, parent);
  recording_ids_.emplace(path, id);
  return id;
}

std::vector<ViewItem> ViewCatalog::Items() const {
  std::lock_guard lock(items_mutex_);
  return {items_.begin(), items_.end()};
}

const ViewItem* ViewCatalog::Find(std::string_view id) const {
  std::lock_guard lock(items_mutex_);
  return FindLocked(id);
}

const ViewItem* ViewCatalog::FindLocked(std::string_view id) const {
  for (const ViewItem& item : items_) {
    if (item.id == id) return &item;
  }
  return nullptr;
}

std::string ViewCatalog::RecordingIdOf(const std::string& path) const {
  std::lock_guard lock(items_mutex_);
  const auto found = recording_ids_.find(path);
  return found == recording_ids_.end() ? "" : found->second;
}

std::vector<ViewItem> ViewCatalog::ChildrenOf(const std::string& parent) const {
  std::lock_guard lock(items_mutex_);
  std::vector<ViewItem> children;
  for (const ViewItem& item : items_) {
    if (item.parent == parent) children.push_back(item);
  }
  return children;
}

nlohmann::json ViewCatalog::ItemsJson() const {
  nlohmann::json items = nlohmann::json::array();
  for (const ViewItem& item : Items()) {
    nlohmann::json entry = {{"id", item.id}, {"kind", item.kind}, {"label", item.label}, {"path", item.path}};
    if (!item.parent.empty()) entry["parent"] = item.parent;
    items.push_back(std::move(entry));
  }
  return items;
}

std::shared_ptr<const evaluation::Recording> ViewCatalog::Recording(std::string_view id) {
  const ViewItem* item = Find(id);
  if (item == nullptr || item->kind != "recording") return nullptr;
  // A robot run's recordings are written while the robot moves (orcs-robot --view): read what is there.
  const ViewItem* parent = item->parent.empty() ? nullptr : Find(item->parent);
  evaluation::RecordingLimits limits;
  limits.allow_unfinished = parent != nullptr && parent->kind == "robot";
  std::error_code error;
  const std::uintmax_t bytes = fs::file_size(item->path, error);
  const fs::file_time_type modified = fs::last_write_time(item->path, error);
  std::lock_guard lock(mutex_);
  const auto cached = cache_.find(id);
  if (cached != cache_.end() && (error || (cached->second.bytes == bytes && cached->second.modified == modified))) {
    return cached->second.recording;
  }
  constexpr std::size_t kKept = 16;  // parsed recordings kept in memory
  if (cached != cache_.end()) {
    cache_.erase(cached);
  } else if (cache_.size() >= kKept) {
    cache_.erase(cache_.begin());
  }
  auto recording = std::make_shared<const evaluation::Recording>(evaluation::ReadRecording(item->path, limits));
  cache_.insert_or_assign(std::string(id), Cached{recording, bytes, modified});
  return recording;
}

std::optional<nlohmann::json> ViewCatalog::BatchJson(std::string_view id) {
  const ViewItem* item = Refreshed(id, "batch");
  if (item == nullptr) return std::nullopt;
  const fs::path folder(item->path);
  const fs::path file = IsFile(folder / "results.jsonl") ? folder / "results.jsonl" : folder / "results.jsonl.partial";
  std::istringstream lines(ReadTable(file));
  nlohmann::json jobs = nlohmann::json::array();
  std::vector<std::string> terms;
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (line.empty()) continue;
    const nlohmann::json result = ParseJson(line, file.string() + ":" + std::to_string(number));
    if (!result.is_object()) continue;
    const std::string job = result.value("id", "");
    nlohmann::json entry = {{"job", job},
                            {"status", result.value("status", "")},
                            {"fitness", result.contains("fitness") ? result["fitness"] : nlohmann::json(nullptr)},
                            {"seed", result.contains("seed") ? result["seed"] : nlohmann::json(nullptr)},
                            {"terms", result.value("terms", nlohmann::json::object())},
                            {"message", result.value("message", "")}};
    for (const auto& [term, value] : entry["terms"].items()) {
      if (std::find(terms.begin(), terms.end(), term) == terms.end()) terms.push_back(term);
    }
    const std::string recording = RecordingIdOf((folder / "recordings" / (job + kRecordingExtension)).string());
    entry["recording"] = recording.empty() ? nlohmann::json(nullptr) : nlohmann::json(recording);
    jobs.push_back(std::move(entry));
  }
  nlohmann::json columns = {"job", "status", "fitness", "seed"};
  for (const std::string& term : terms) columns.push_back(term);
  return nlohmann::json{{"name", item->label}, {"columns", columns}, {"jobs", jobs}, {"progress", ProgressOf(folder)}};
}

std::optional<nlohmann::json> ViewCatalog::EvolveJson(std::string_view id) {
  const ViewItem* item = Refreshed(id, "evolve");
  if (item == nullptr) return std::nullopt;
  const fs::path folder(item->path);
  std::istringstream lines(ReadTable(folder / "fitness.csv"));
  std::string line;
  std::vector<std::string> names;
  nlohmann::json generations = nlohmann::json::array();
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    if (names.empty()) {
      names = fields;
      continue;
    }
    nlohmann::json row = nlohmann::json::object();
    for (std::size_t i = 0; i < names.size() && i < fields.size(); ++i) row[names[i]] = NumberOrNull(fields[i]);
    generations.push_back(std::move(row));
  }
  nlohmann::json genome = nullptr;
  const std::string genome_text = ReadTable(folder / "best_genome.json");
  if (!genome_text.empty()) genome = ParseJson(genome_text, (folder / "best_genome.json").string());
  const std::string winner = RecordingIdOf((folder / "best" / "recordings" / "winner.orcsrec").string());
  return nlohmann::json{{"name", item->label},
                        {"generations", generations},
                        {"best_genome", genome},
                        {"recording", winner.empty() ? nlohmann::json(nullptr) : nlohmann::json(winner)},
                        {"progress", ProgressOf(folder)}};
}

std::optional<nlohmann::json> ViewCatalog::GapJson(std::string_view id) {
  const ViewItem* item = Refreshed(id, "gap");
  if (item == nullptr) return std::nullopt;
  const fs::path folder(item->path);
  const std::string report_text = ReadTable(folder / "report.json");  // "" while the diagnosis runs
  const nlohmann::json report =
      report_text.empty() ? nlohmann::json(nullptr) : ParseJson(report_text, (folder / "report.json").string());
  nlohmann::json effect = nullptr;
  if (report.is_object() && report.contains("verdict") && report["verdict"].is_object()) {
    effect = report["verdict"].value("effect", nlohmann::json(nullptr));
  }
  // replays/<run>.orcsrec (fitted model), <run>.given.orcsrec (model as given), <run>.measured.orcsrec (measured).
  std::map<std::string, nlohmann::json> runs;
  for (const ViewItem& child : ChildrenOf(item->id)) {
    std::string name = child.label;
    std::string role = "simulated";
    for (const char* suffix : {".given", ".measured"}) {
      if (name.ends_with(suffix)) {
        role = std::string(suffix + 1);
        name.resize(name.size() - std::string_view(suffix).size());
      }
    }
    nlohmann::json& run = runs[name];
    if (run.is_null()) run = {{"name", name}, {"simulated", nullptr}, {"given", nullptr}, {"measured", nullptr}};
    run[role] = child.id;
  }
  nlohmann::json list = nlohmann::json::array();
  for (auto& [name, run] : runs) list.push_back(std::move(run));
  return nlohmann::json{{"name", item->label}, {"missing_effect", effect}, {"runs", list}, {"progress", ProgressOf(folder)}};
}

std::optional<nlohmann::json> ViewCatalog::RobotJson(std::string_view id) {
  const ViewItem* item = Refreshed(id, "robot");
  if (item == nullptr) return std::nullopt;
  const fs::path folder(item->path);
  const std::string about_text = ReadTable(folder / "robot_run.json");
  const nlohmann::json about =
      about_text.empty() ? nlohmann::json(nullptr) : ParseJson(about_text, (folder / "robot_run.json").string());
  nlohmann::json answer = {{"name", item->label}, {"run", about}, {"robot", nullptr}, {"twin", nullptr},
                           {"bytes", nlohmann::json::object()}, {"progress", ProgressOf(folder)}};
  for (const ViewItem& child : ChildrenOf(item->id)) {
    if (child.label != "robot" && child.label != "twin") continue;
    answer[child.label] = child.id;
    std::error_code error;
    answer["bytes"][child.label] = fs::file_size(child.path, error);
  }
  return answer;
}

nlohmann::json ViewCatalog::ReplaysJson() {
  nlohmann::json replays = nlohmann::json::array();
  for (const ViewItem& item : Items()) {
    if (item.kind != "batch" || !item.parent.empty()) continue;
    const nlohmann::json progress = ProgressOf(item.path);
    if (!progress.is_object() || !progress.contains("broker_batch") || !progress["broker_batch"].is_string()) continue;
    Refreshed(item.id, "batch");
    for (const ViewItem& child : ChildrenOf(item.id)) {
      replays.push_back({{"batch", progress["broker_batch"]}, {"job", child.label}, {"recording", child.id}});
    }
  }
  return replays;
}

}  // namespace orcs::viewer
