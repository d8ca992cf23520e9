// The command line of orcs-batch (docs/batch.md):
//   orcs-batch run SCENARIO.json [--genomes FILE.jsonl | --genome JSON] [--jobs N] [--seed S] [--workers N]
//                                [--out DIR] [--time-limit SECONDS] [--record JOBS] [--curve-keys DIR]
//   orcs-batch submit --broker ENDPOINT SCENARIO.json ... (the same job options, no --workers)
//   orcs-batch sweep SCENARIO.json --param PATH=LOW:HIGH:STEPS... [--genome JSON] [--jobs N] [--seed S]
//                                  [--workers N | --broker ENDPOINT] [--out DIR]
//   orcs-batch sweep SCENARIO.json --sample lhs --samples N --param PATH=LOW:HIGH... [--sample-seed S] ...
//   orcs-batch run|submit|sweep --resume DIR: completes the interrupted batch in DIR (docs/batch.md)
//   orcs-batch evolve SCENARIO.json [--generations G] [--population P] [--algorithm NAME] [--seed S]
//                                   [--validate N] [--out DIR | --resume DIR] [--workers N | --broker ENDPOINT]
//   orcs-batch compare A B [--tolerance X] [--out DIR] [--no-plot]: the same jobs of two runs, what changed
//   orcs-batch resolve SCENARIO.json: prints the scenario with every referenced file inlined (what a job carries)
//   orcs-batch regress SUITE.json [--baseline FILE] [--update-baseline] [--junit FILE.xml] [--set PATH=VALUE]...
//                                 [--workers N | --broker ENDPOINT] [--out DIR]   (docs/regress.md)
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace orcs::batch {

enum class Command { kRun, kSubmit, kSweep, kEvolve, kResolve, kRegress, kCompare };

struct BatchOptions {
  Command command = Command::kRun;
  std::string scenario;              ///< SCENARIO.json
  std::string genomes;               ///< --genomes FILE.jsonl: one genome per line ("" = none)
  std::string genome;                ///< --genome JSON or @FILE ("" = none)
  int jobs = 1;                      ///< --jobs N: jobs (seeds) per genome or sweep point, ≥ 1
  std::uint64_t seed = 1;            ///< --seed S: seed of the first job of each genome or point
  bool seed_given = false;           ///< --seed was on the command line (evolve: else the scenario's)
  int workers = 0;                   ///< --workers N: local workers (0 = one per core, at most one per job)
  std::string broker;                ///< --broker ENDPOINT: a running broker's client endpoint ("" = embedded)
  std::string out;                   ///< --out DIR ("" = runs/<scenario name>)
  double time_limit_seconds = 0.0;   ///< --time-limit: wall-clock seconds per job (0 = scene::DefaultTimeLimitSeconds)
  std::string record;                ///< --record JOBS: "all" or indices "0,3-5" of the jobs recorded ("" = none)
  double heartbeat_seconds = 1.0;    ///< --heartbeat: the client's (and embedded broker's) heartbeat interval
  std::vector<std::string> params;   ///< --param PATH=LOW:HIGH:STEPS, PATH=LOW:HIGH (lhs) or PATH=V1,V2,... (sweep)
  std::string sample = "grid";       ///< --sample grid|lhs (sweep): every combination, or a Latin hypercube sample
  int samples = 0;                   ///< --samples N (sweep --sample lhs): points of the Latin hypercube, ≥ 1
  std::uint64_t sample_seed = 0;     ///< --sample-seed S: the Latin hypercube's seed (when not given: --seed)
  bool sample_seed_given = false;    ///< whether --sample-seed was given
  bool quiet = false;                ///< --quiet: no progress display
  /// --curve-keys DIR: CURVE keys (docs/security.md); client.key/.pub and broker.pub, and for the embedded
  /// broker and local workers also broker.key, worker.key/.pub and allowed_*/ ("" = plain TCP)
  std::string curve_keys;
  // evolve (clients/evolve, docs/evolution.md): unset values keep the scenario's "evolution" section
  std::string algorithm;             ///< --algorithm NAME ("" = unset)
  int population = 0;                ///< --population P (0 = unset)
  int generations = -1;              ///< --generations G (< 0 = unset)
  int validate = -1;                 ///< --validate N: fresh seeds the winner is re-run on (< 0 = unset)
  bool fresh_sets = false;           ///< evolve --fresh-sets: new parameter sets every generation
  /// --resume DIR: evolve continues the run whose checkpoint is in DIR; run, submit and sweep complete the
  /// interrupted batch in DIR (its settings from DIR/batch.json, clients/batch/batch_manifest.h)
  std::string resume;
  bool no_plot = false;              ///< --no-plot: skip fitness.png
  std::string suite;                 ///< regress: SUITE.json
  std::string baseline;              ///< regress --baseline FILE ("" = SUITE.baseline.json beside the suite)
  /// --engine NAME: every job's /Simulation/Engine ("" = the scenario's; regress: ODE, whose baseline it picks)
  std::string engine;
  bool update_baseline = false;      ///< regress --update-baseline: record the baseline from this run
  std::string junit;                 ///< regress --junit FILE.xml ("" = no JUnit report)
  std::vector<std::string> sets;     ///< regress --set PATH=VALUE: an override of every case, outside the fingerprint
  std::vector<std::string> runs;     ///< compare: the two results files or folders, A then B
  double tolerance = 0.0;            ///< compare --tolerance: a figure changed when it moved by more (0: any bit)
  /// The options given on the command line, by name ("--jobs", "scenario"): a resume tells them from defaults.
  std::set<std::string> given;
};

struct ParsedBatchOptions {
  BatchOptions options;
  int exit_code = -1;  ///< ≥ 0: exit now with this code (help printed: 0; bad options reported: 2)
};

/// The command that continues the interrupted run in `folder` (docs/batch.md, "Ctrl-C"): orcs-batch run|submit|sweep|
/// evolve --resume FOLDER, with the options given that a resume does not read from the folder (--broker,
/// --workers, --curve-keys, --heartbeat). As words, for interrupt.h's ShellCommand.
std::vector<std::string> ResumeCommandLine(const BatchOptions& options, const std::string& folder);

/// Parses argv; --help prints help (exit 0); a bad or missing option prints one line to stderr (exit 2).
ParsedBatchOptions ParseBatchOptions(int argc, const char* const* argv);

}  // namespace orcs::batch
