#include "clients/evolve/evolution_checkpoint.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/fnv1a64.h"
#include "model/core/json_node.h"
#include "model/core/text_file.h"

namespace orcs::evolve {
namespace {

constexpr const char* kFormat = "orcs evolve checkpoint 1";

// A stable digest of the resolved scenario (what the jobs carry).
std::string Digest(const std::string& text) {
  Fnv1a64 fnv;
  fnv.AddBytes(text);
  return fnv.Hex();
}

// NaN (a generation without ok jobs) is stored as null.
nlohmann::ordered_json NumberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

double NumberOrNaN(const JsonNode& node, const std::string& key) {
  const JsonNode value = node.At(key);
  return value.value().is_null() ? std::numeric_limits<double>::quiet_NaN() : value.Number("a number or null");
}

nlohmann::ordered_json RecordJson(const GenerationRecord& r) {
  return {{"generation", r.generation},
          {"evaluations", r.evaluations},
          {"failed", r.failed},
          {"best", NumberOrNull(r.best)},
          {"mean", NumberOrNull(r.mean)},
          {"median", NumberOrNull(r.median)},
          {"worst", NumberOrNull(r.worst)},
          {"best_so_far", NumberOrNull(r.best_so_far)},
          {"seconds", r.seconds}};
}

GenerationRecord ReadRecord(const JsonNode& node) {
  GenerationRecord r;
  r.generation = node.At("generation").Integer("a generation");
  r.evaluations = node.At("evaluations").Unsigned("a count");
  r.failed = node.At("failed").Unsigned("a count");
  r.best = NumberOrNaN(node, "best");
  r.mean = NumberOrNaN(node, "mean");
  r.median = NumberOrNaN(node, "median");
  r.worst = NumberOrNaN(node, "worst");
  r.best_so_far = NumberOrNaN(node, "best_so_far");
  r.seconds = node.At("seconds").Number("seconds");
  return r;
}

std::string Describe(const nlohmann::ordered_json& value) { return value.dump(); }

// The first fingerprint field that differs, in words.
void CheckFingerprint(const std::string& file, const nlohmann::ordered_json& found,
                      const nlohmann::ordered_json& expected) {
  if (found.value("scenario", "") != expected.value("scenario", "") ||
      found.value("scenario_digest", "") != expected.value("scenario_digest", "")) {
    throw InputError(file + ": written for scenario '" + found.value("scenario", "?") + "' (" +
                     found.value("scenario_file", "?") + ", digest " + found.value("scenario_digest", "?") +
                     "), not for '" + expected.value("scenario", "?") + "' (" + expected.value("scenario_file", "?") +
                     ", digest " + expected.value("scenario_digest", "?") +
                     "): resume with the scenario it was made with, or start afresh in another --out folder");
  }
  for (const auto& [key, value] : expected.items()) {
    if (key == "scenario_file") continue;  // the same scenario may be given by another path
    if (!found.contains(key) || found.at(key) != value) {
      throw InputError(file + ": made with " + key + " " + (found.contains(key) ? Describe(found.at(key)) : "none") +
                       ", this run has " + Describe(value) +
                       ": give the same settings to resume, or start afresh in another --out folder");
    }
  }
  for (const auto& [key, value] : found.items()) {  // a setting only the checkpoint has (fresh_sets)
    if (!expected.contains(key)) {
      throw InputError(file + ": made with " + key + " " + Describe(value) +
                       ", this run has none: give the same settings to resume, or start afresh in another --out "
                       "folder");
    }
  }
}

}  // namespace

nlohmann::ordered_json Fingerprint(const runtime::ScenarioInput& input, const EvolutionSettings& settings) {
  nlohmann::ordered_json bounds = nlohmann::ordered_json::array();
  for (const GeneBounds& b : settings.bounds) bounds.push_back({b.low, b.high});
  nlohmann::ordered_json fingerprint = {{"scenario", input.scenario.name},
          {"scenario_file", input.path},
          {"scenario_digest", Digest(input.resolved_json)},
          {"algorithm", AlgorithmName(settings.algorithm)},
          {"population", settings.population},
          {"seed", settings.seed},
          {"sigma", settings.sigma},
          {"bounds", bounds},
          {"start", settings.start}};
  if (settings.fresh_sets) fingerprint["fresh_sets"] = true;  // absent when false: older checkpoints stay valid
  return fingerprint;
}

EvolutionCheckpoint CheckpointOf(const Evolution& evolution, nlohmann::ordered_json fingerprint,
                                 nlohmann::ordered_json run) {
  return {std::move(fingerprint), evolution.history(), evolution.champion(), evolution.SaveState(), std::move(run)};
}

nlohmann::ordered_json RunSettings(const std::string& scenario_path, const std::string& engine, int generations,
                                   int validate, double time_limit_seconds) {
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::weakly_canonical(std::filesystem::absolute(scenario_path), error);
  return {{"scenario_path", error ? scenario_path : absolute.string()},
          {"engine", engine},
          {"generations", generations},
          {"validate", validate},
          {"time_limit_seconds", time_limit_seconds}};
}

nlohmann::ordered_json ReadCheckpointSettings(const std::string& folder) {
  const std::string path = (std::filesystem::path(folder) / "checkpoint.json").string();
  if (!std::filesystem::exists(path)) {
    throw InputError("--resume " + folder + ": no checkpoint.json there (not an orcs-batch evolve output folder)");
  }
  const nlohmann::json document = ParseJson(ReadTextFile(path), path);
  if (!document.is_object() || !document.contains("fingerprint") || !document["fingerprint"].is_object()) {
    throw InputError(path, 0, "not an evolution checkpoint (no \"fingerprint\" object)");
  }
  return {{"fingerprint", nlohmann::ordered_json(document["fingerprint"])},
          {"run", document.contains("run") ? nlohmann::ordered_json(document["run"]) : nlohmann::ordered_json::object()}};
}

void WriteCheckpoint(const std::string& folder, const EvolutionCheckpoint& checkpoint) {
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const GenerationRecord& record : checkpoint.history) history.push_back(RecordJson(record));
  const nlohmann::ordered_json document = {{"format", kFormat},
                                           {"fingerprint", checkpoint.fingerprint},
                                           {"champion",
                                            {{"genome", checkpoint.champion.genome},
                                             {"fitness", checkpoint.champion.fitness},
                                             {"generation", checkpoint.champion.generation},
                                             {"seed", checkpoint.champion.seed}}},
                                           {"history", history},
                                           {"pagmo_state", checkpoint.pagmo_state},
                                           {"run", checkpoint.run}};
  AtomicFile file((std::filesystem::path(folder) / "checkpoint.json").string());
  file.stream() << document.dump(1) << "\n";
  file.Commit();
}

EvolutionCheckpoint ReadCheckpoint(const std::string& folder, const nlohmann::ordered_json& expected_fingerprint) {
  const std::string path = (std::filesystem::path(folder) / "checkpoint.json").string();
  if (!std::filesystem::exists(path)) {
    throw InputError("--resume " + folder + ": no checkpoint.json there (not an orcs-batch evolve output folder)");
  }
  const nlohmann::json document = ParseJson(ReadTextFile(path), path);
  const JsonNode root(document, "", path);
  root.ExpectOnly({"format", "fingerprint", "champion", "history", "pagmo_state", "run"});
  if (root.At("format").String("a format name") != kFormat) root.At("format").Fail(std::string("\"") + kFormat + "\"");
  CheckFingerprint(path, nlohmann::ordered_json(root.At("fingerprint").value()), expected_fingerprint);
  EvolutionCheckpoint checkpoint;
  checkpoint.fingerprint = expected_fingerprint;
  const JsonNode champion = root.At("champion");
  checkpoint.champion.genome = champion.At("genome").Numbers("the champion's genes");
  checkpoint.champion.fitness = champion.At("fitness").Number("a fitness");
  checkpoint.champion.generation = champion.At("generation").Integer("a generation");
  // Checkpoints from before fresh parameter sets hold no seed: their champion's jobs all had the run's seed.
  checkpoint.champion.seed = champion.Has("seed") ? champion.At("seed").Unsigned("a seed ≥ 0")
                                                  : expected_fingerprint.at("seed").get<std::uint64_t>();
  for (const JsonNode& record : root.At("history").Elements()) checkpoint.history.push_back(ReadRecord(record));
  if (checkpoint.history.empty()) root.At("history").Fail("at least generation 0");
  checkpoint.pagmo_state = root.At("pagmo_state").String("the algorithm's state");
  return checkpoint;
}

}  // namespace orcs::evolve
