#include "clients/batch/batch_manifest.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text_file.h"

namespace orcs::batch {
using runtime::Genome;
using runtime::ScenarioInput;
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr const char* kFormat = "orcs-batch-manifest/1";

std::string CommandName(Command command) {
  switch (command) {
    case Command::kRun: return "run";
    case Command::kSubmit: return "submit";
    case Command::kSweep: return "sweep";
    default: return "other";
  }
}

// A path as the manifest keeps it: absolute, so that a resume from another directory finds the same file.
std::string Absolute(const std::string& path) {
  if (path.empty() || path.front() == '@') return path;  // --genome @FILE stays as given
  std::error_code error;
  const fs::path absolute = fs::weakly_canonical(fs::absolute(path), error);
  return error ? path : absolute.string();
}

Json GenomeValues(const std::vector<Genome>& genomes) {
  Json values = Json::array();
  for (const Genome& genome : genomes) values.push_back(genome.value);
  return values;
}

std::string ManifestPath(const std::string& folder) { return (fs::path(folder) / kManifestFile).string(); }

Json ReadManifest(const std::string& folder) {
  const std::string path = ManifestPath(folder);
  Json manifest;
  try {
    manifest = Json::parse(ReadTextFile(path, kMaxInputFileBytes, "a batch manifest"));
  } catch (const Json::exception& error) {
    throw InputError(path, 0, std::string("not a batch manifest: ") + error.what());
  }
  if (!manifest.is_object() || manifest.value("format", "") != kFormat) {
    throw InputError(path, 0, std::string("not a batch manifest (expected \"format\": \"") + kFormat + "\")");
  }
  return manifest;
}

// Takes `field` of the manifest into `value`, unless the command line gave `option` with another value.
template <typename T>
void Take(const Json& manifest, const char* field, const BatchOptions& given, const std::string& option, T& value,
          const std::string& folder) {
  T stored;
  try {
    stored = manifest.at(field).get<T>();
  } catch (const Json::exception&) {
    throw InputError(ManifestPath(folder), 0, std::string("\"") + field + "\": missing or of the wrong type");
  }
  if (given.given.count(option) != 0 && !(value == stored)) {
    throw InputError(option + ": the batch in " + folder + " was started with " + Json(stored).dump() +
                     ", not " + Json(value).dump() + "; leave the option out to resume it (its settings are in " +
                     ManifestPath(folder) + ")");
  }
  value = stored;
}

}  // namespace

void WriteBatchManifest(const std::string& folder, const BatchOptions& options, const ScenarioInput& input,
                        const std::vector<Genome>& genomes) {
  Json manifest = {{"format", kFormat},
                   {"command", CommandName(options.command)},
                   {"scenario", Absolute(options.scenario)},
                   {"genomes", Absolute(options.genomes)},
                   {"genome", options.genome},
                   {"jobs", options.jobs},
                   {"seed", options.seed},
                   {"time_limit_seconds", options.time_limit_seconds},
                   {"record", options.record},
                   {"engine", options.engine},
                   {"params", options.params},
                   {"sample", options.sample},
                   {"samples", options.samples},
                   {"sample_seed", options.sample_seed},
                   {"sample_seed_given", options.sample_seed_given},
                   {"resolved_scenario", input.resolved_json},
                   {"genome_values", GenomeValues(genomes)}};
  AtomicFile file(ManifestPath(folder));
  file.stream() << manifest.dump(1) << "\n";
  file.Commit();
}

BatchOptions ResumedOptions(const BatchOptions& given) {
  const std::string& folder = given.resume;
  const Json manifest = ReadManifest(folder);
  BatchOptions options = given;
  const std::string command = manifest.value("command", "");
  if ((command == "sweep") != (given.command == Command::kSweep)) {
    throw InputError("--resume: " + folder + " holds a " + command + " batch; resume it with `orcs-batch " +
                     (command == "sweep" ? "sweep" : "run") + " --resume " + folder + "`");
  }
  if (given.given.count("--out") != 0 && Absolute(given.out) != Absolute(folder)) {
    throw InputError("--out " + given.out + ": a resumed batch writes into its own folder, " + folder +
                     "; leave --out out");
  }
  options.out = folder;
  if (given.given.count("scenario") != 0) options.scenario = Absolute(given.scenario);
  Take(manifest, "scenario", given, "scenario", options.scenario, folder);
  if (given.given.count("--genomes") != 0) options.genomes = Absolute(given.genomes);
  Take(manifest, "genomes", given, "--genomes", options.genomes, folder);
  Take(manifest, "genome", given, "--genome", options.genome, folder);
  Take(manifest, "jobs", given, "--jobs", options.jobs, folder);
  Take(manifest, "seed", given, "--seed", options.seed, folder);
  Take(manifest, "time_limit_seconds", given, "--time-limit", options.time_limit_seconds, folder);
  Take(manifest, "record", given, "--record", options.record, folder);
  Take(manifest, "engine", given, "--engine", options.engine, folder);
  Take(manifest, "params", given, "--param", options.params, folder);
  Take(manifest, "sample", given, "--sample", options.sample, folder);
  Take(manifest, "samples", given, "--samples", options.samples, folder);
  Take(manifest, "sample_seed", given, "--sample-seed", options.sample_seed, folder);
  Take(manifest, "sample_seed_given", given, "", options.sample_seed_given, folder);  // follows --sample-seed
  return options;
}

void CheckResumedInputs(const std::string& folder, const ScenarioInput& input, const std::vector<Genome>& genomes) {
  const Json manifest = ReadManifest(folder);
  const std::string why = " has changed since the batch in " + folder +
                          " started, so its remaining jobs would not be the interrupted batch's; start a new batch "
                          "with another --out instead";
  if (manifest.value("resolved_scenario", "") != input.resolved_json) throw InputError(input.path, 0, "the scenario" + why);
  if (manifest.value("genome_values", Json::array()) != GenomeValues(genomes)) {
    const std::string source = genomes.empty() ? "--genome" : genomes.front().source;
    throw InputError(source, 0, "the genomes" + why);
  }
}

}  // namespace orcs::batch
