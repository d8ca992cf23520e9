// DIR/batch.json: what `orcs-batch run|submit|sweep` was started with, so that `--resume DIR` completes exactly the
// batch that was interrupted (docs/batch.md, "Resuming a batch"). It holds the job options, the scenario as its
// jobs carried it (every referenced file inlined) and the genomes; a resume takes its settings from here, accepts
// the same settings again on the command line, and refuses a contradiction or a scenario or genome file that has
// changed since, naming it.
#pragma once

#include <string>
#include <vector>

#include "clients/batch/batch_options.h"
#include "clients/runtime/batch_input.h"

namespace orcs::batch {

/// The manifest's file name within the output folder.
inline constexpr const char* kManifestFile = "batch.json";

/// Writes DIR/batch.json (atomically) for a batch started with `options`, whose resolved scenario and genomes
/// are those given. Throws InputError when it cannot be written.
void WriteBatchManifest(const std::string& folder, const BatchOptions& options, const runtime::ScenarioInput& input,
                        const std::vector<runtime::Genome>& genomes);

/// `given` (with --resume DIR) completed by DIR/batch.json's job settings. Throws InputError naming batch.json for
/// a missing or malformed manifest, and naming the option for one that contradicts it ("--jobs 50: the batch
/// in DIR was started with 40").
BatchOptions ResumedOptions(const BatchOptions& given);

/// Throws InputError naming the file when the scenario (as resolved) or the genomes differ from the manifest's:
/// resuming would mix the jobs of two batches.
void CheckResumedInputs(const std::string& folder, const runtime::ScenarioInput& input, const std::vector<runtime::Genome>& genomes);

}  // namespace orcs::batch
