// The checkpoint of an orcs-batch evolve run: DIR/checkpoint.json, rewritten (atomically) after every generation.
// It holds what the search depends on — a fingerprint of the scenario and the settings — and where the search
// is: the pagmo algorithm and population (exact), the champion and the history. `--resume DIR` reads it back and
// refuses one made for another scenario or other settings, before anything is submitted.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clients/evolve/evolution.h"
#include "clients/evolve/evolution_settings.h"
#include "clients/runtime/batch_input.h"

namespace orcs::evolve {

struct EvolutionCheckpoint {
  nlohmann::ordered_json fingerprint;     ///< scenario and settings the run was made with (Fingerprint())
  std::vector<GenerationRecord> history;  ///< one record per generation done
  Champion champion;                      ///< the best genome so far
  std::string pagmo_state;                ///< Evolution::SaveState()
  /// How the run was started, for `--resume DIR` alone (RunSettings()); empty in checkpoints from before it.
  nlohmann::ordered_json run;
};

/// What `evolve` was started with beyond the fingerprint: the scenario file (absolute), engine, generations,
/// validation seeds and time limit — so that `--resume DIR` needs no other option.
nlohmann::ordered_json RunSettings(const std::string& scenario_path, const std::string& engine, int generations,
                                   int validate, double time_limit_seconds);

/// FOLDER/checkpoint.json's fingerprint and run settings, without checking them against anything: what a resume
/// takes its settings from. Throws InputError naming the file when there is none or it is damaged.
nlohmann::ordered_json ReadCheckpointSettings(const std::string& folder);

/// What must not change for a run to be resumed: the scenario's name and a digest of its resolved content, the
/// algorithm, population, seed, sigma, bounds and start genome. (Not the generations or validation seeds.)
nlohmann::ordered_json Fingerprint(const runtime::ScenarioInput& input, const EvolutionSettings& settings);

/// The checkpoint of `evolution` now.
EvolutionCheckpoint CheckpointOf(const Evolution& evolution, nlohmann::ordered_json fingerprint,
                                 nlohmann::ordered_json run);

/// Writes FOLDER/checkpoint.json atomically. Throws InputError when it cannot be written.
void WriteCheckpoint(const std::string& folder, const EvolutionCheckpoint& checkpoint);

/// Reads FOLDER/checkpoint.json and checks it belongs to `expected_fingerprint`. Throws InputError naming the
/// file and what differs ("written for scenario 'a' ..., not 'b'"; "algorithm 'cmaes', this run 'de'"), or
/// that there is no checkpoint, or that it is damaged.
EvolutionCheckpoint ReadCheckpoint(const std::string& folder, const nlohmann::ordered_json& expected_fingerprint);

}  // namespace orcs::evolve
