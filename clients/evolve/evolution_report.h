// The files an orcs-batch evolve run leaves in its folder besides the checkpoint (docs/evolution.md):
//   fitness.csv        one line per generation (GenerationRecord), rewritten after every generation
//   best_genome.json   the champion's genome as a JSON array: `orcs-sim --scenario S --genome @best_genome.json`
// Both are written atomically, so an interrupted run leaves complete files.
#pragma once

#include <string>
#include <vector>

#include "clients/evolve/evolution.h"

namespace orcs::evolve {

/// Writes FOLDER/fitness.csv: "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds", numbers
/// that read back to the same doubles, an empty field for a NaN. Throws InputError.
void WriteFitnessCsv(const std::string& folder, const std::vector<GenerationRecord>& history);

/// Writes FOLDER/best_genome.json (nothing when the champion is still empty). Throws InputError.
void WriteBestGenome(const std::string& folder, const Champion& champion);

/// One line for the terminal: "generation 3/30: best 1.25, mean 0.4 (16 jobs, 0 failed, 4.1 s); best so far 1.3".
std::string GenerationLine(const GenerationRecord& record, int generations);

}  // namespace orcs::evolve
