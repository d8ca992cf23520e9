#include "clients/batch/batch_options.h"

#include <CLI/CLI.hpp>
#include <iostream>
#include <limits>

#include "clients/runtime/batch_input.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/scene/engine_names.h"
#include "net/cli_style.h"

namespace orcs::batch {
using runtime::ParseJobSelection;
namespace {

// --time-limit: 115 days at most (a job may carry up to evaluation::kMaxJobTimeLimitSeconds).
constexpr double kMaxTimeLimitOption = 1e7;

// What every command that runs a batch shares: where results go, the connection, the progress display.
void AddSessionOptions(CLI::App& command, BatchOptions& o, const std::string& out_help) {
  command.add_option("--out", o.out, out_help);
  command.add_option("--heartbeat", o.heartbeat_seconds,
                 "seconds between heartbeats (default 1; the broker waits for the slower of its pace and this)")
      ->check(cli::NumberIn(0.001, 3600.0));
  command.add_flag("--quiet", o.quiet, "no progress display");
  command.add_option("--curve-keys", o.curve_keys, "folder of CURVE keys: encrypt and authenticate (docs/security.md)")
      ->check(CLI::Validator([](const std::string& dir) { return dir.empty() ? "needs a folder" : ""; }, "DIR"));
}

// --engine: the physics engine of every job, over the scenario's "values".
void AddEngineOption(CLI::App& command, BatchOptions& o, const std::string& help) {
  command.add_option("--engine", o.engine, help)->transform(CLI::IsMember(scene::EngineNames(), CLI::ignore_case));
}

// The options every subcommand shares: what the jobs are and where the results go.
void AddJobOptions(CLI::App& command, BatchOptions& o, bool many_genomes) {
  command.add_option("scenario", o.scenario, "the scenario file (docs/scenarios.md); required unless --resume");
  command.add_option("--resume", o.resume,
                     "complete the interrupted batch in this folder: run only its jobs without a result, with the "
                     "settings it was started with (DIR/batch.json)");
  if (many_genomes) {
    command.add_option("--genomes", o.genomes, "JSON-lines file, one genome per line: one job per genome and seed");
  }
  command.add_option("--genome", o.genome, "one genome as JSON text, or @FILE (default: the scenario's \"genome\")");
  command.add_option("--jobs", o.jobs, many_genomes ? "jobs per genome, seeds S, S+1, ... (default 1)"
                                                    : "jobs per grid point, seeds S, S+1, ... (default 1)")
      ->check(CLI::Range(1, 1000000));
  command.add_option("--seed", o.seed, "seed of the first job (default 1)")->check(cli::Seed());
  command.add_option("--time-limit", o.time_limit_seconds, "wall-clock seconds per job (default 0: 30 s + 10 s per simulated second of the job)")
      ->check(cli::NumberIn(0.0, kMaxTimeLimitOption));
  command.add_option("--record", o.record,
                     "record these jobs for orcs-view into OUT/recordings/JOB.orcsrec: all, or job indices such as "
                     "0,3-5 (docs/recording.md)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            try {
              ParseJobSelection(text, std::numeric_limits<std::size_t>::max());
              return std::string();
            } catch (const InputError& error) {  // CLI11 names the option itself
              const std::string message = error.what();
              const std::string prefix = error.source() + ": ";
              return message.starts_with(prefix) ? message.substr(prefix.size()) : message;
            }
          },
          "JOBS"));
  AddEngineOption(command, o, "physics engine of every job (/Simulation/Engine, over the scenario's values)");
  AddSessionOptions(command, o, "output folder (default runs/<scenario name>)");
}

void AddWorkersOption(CLI::App& command, BatchOptions& o) {
  command.add_option("--workers", o.workers, "local worker processes (default: one per core)")
      ->check(CLI::Range(1, 4096));
}

// evolve's own options; its job options are run's (one genome per job, no --jobs or --genome: evolution makes them).
CLI::App* AddEvolveCommand(CLI::App& app, BatchOptions& o) {
  CLI::App* evolve = app.add_subcommand("evolve", "evolve the scenario's genome, every generation one batch");
  evolve->add_option("scenario", o.scenario,
                     "the scenario file, with an \"evolution\" section (docs/evolution.md); required unless --resume");
  evolve->add_option("--generations", o.generations, "generations after the first (default: the scenario's)")
      ->check(CLI::Range(0, 1000000));
  evolve->add_option("--population", o.population, "genomes per generation (default: the scenario's)")
      ->check(CLI::Range(1, 100000));
  evolve->add_option("--algorithm", o.algorithm, "cmaes, xnes, sga, de or pso_gen (default: the scenario's, else cmaes)");
  evolve->add_option("--seed", o.seed, "seed of the jobs' parameter sets and of the algorithm (default: the scenario's)")
      ->check(cli::Seed());
  evolve->add_option("--validate", o.validate, "fresh seeds the winner is run on at the end (default 8)")
      ->check(CLI::Range(0, 100000));
  evolve->add_flag("--fresh-sets", o.fresh_sets,
                   "new parameter sets every generation (a seed per generation) instead of the same sets throughout");
  AddEngineOption(*evolve, o, "physics engine of every job (/Simulation/Engine, over the scenario's values)");
  AddSessionOptions(*evolve, o, "output folder (default runs/<scenario name>-evolve)");
  evolve->add_option("--resume", o.resume,
                     "continue the run whose checkpoint is in this folder, with the settings it was started with")
      ->excludes(evolve->get_option("--out"));
  evolve->add_option("--time-limit", o.time_limit_seconds, "wall-clock seconds per job (default 0: 30 s + 10 s per simulated second of the job)")
      ->check(cli::NumberIn(0.0, kMaxTimeLimitOption));
  evolve->add_flag("--no-plot", o.no_plot, "do not draw fitness.png");
  CLI::Option* workers = evolve->add_option("--workers", o.workers, "local worker processes (default: one per core)")
                             ->check(CLI::Range(1, 4096));
  evolve->add_option("--broker", o.broker, "a running broker's client endpoint instead of local workers")
      ->check(cli::Endpoint())
      ->excludes(workers);
  return evolve;
}

// `regress`: a suite against its baseline (docs/regress.md).
CLI::App* AddRegressCommand(CLI::App& app, BatchOptions& o) {
  CLI::App* regress = app.add_subcommand("regress", "run a regression suite and compare it with its baseline");
  regress->add_option("suite", o.suite, "the suite file (docs/regress.md)")->required();
  regress->add_option("--baseline", o.baseline,
                      "the baseline file (default: SUITE.baseline.json beside the suite; SUITE.mujoco.baseline.json "
                      "with --engine MuJoCo)");
  AddEngineOption(*regress, o,
                  "run every case on this physics engine (/Simulation/Engine, default ODE), against that engine's "
                  "baseline");
  regress->add_flag("--update-baseline", o.update_baseline, "record the baseline from this run instead of comparing");
  regress->add_option("--junit", o.junit, "write a JUnit XML report here");
  regress->add_option("--set", o.sets, "PATH=VALUE: override a value in every case, like a model change (repeatable)")
      ->allow_extra_args(false);
  CLI::Option* workers = regress->add_option("--workers", o.workers, "local worker processes (default: one per core)")
                             ->check(CLI::Range(1, 4096));
  regress->add_option("--broker", o.broker, "a running broker's client endpoint instead of local workers")
      ->check(cli::Endpoint())
      ->excludes(workers);
  AddSessionOptions(*regress, o, "output folder (default runs/<suite name>)");
  return regress;
}

CLI::App* AddSubmitCommand(CLI::App& app, BatchOptions& o) {
  CLI::App* submit = app.add_subcommand("submit", "run a batch on a running broker");
  AddJobOptions(*submit, o, true);
  submit->add_option("--broker", o.broker, "the broker's client endpoint, e.g. tcp://127.0.0.1:5555")
      ->required()
      ->check(cli::Endpoint());
  return submit;
}

CLI::App* AddSweepCommand(CLI::App& app, BatchOptions& o) {
  CLI::App* sweep = app.add_subcommand(
      "sweep", "evaluate one genome over a grid or a Latin hypercube sample of repository values: a robustness report");
  AddJobOptions(*sweep, o, false);
  sweep->add_option("--param", o.params,
                    "PATH=LOW:HIGH:STEPS (grid), PATH=LOW:HIGH (lhs) or PATH=V1,V2,... (categories): one axis "
                    "(repeatable; required unless --resume)")
      ->allow_extra_args(false);
  sweep->add_option("--sample", o.sample, "grid: every combination (default); lhs: a Latin hypercube sample")
      ->check(CLI::IsMember({"grid", "lhs"}));
  sweep->add_option("--samples", o.samples, "points of the Latin hypercube (--sample lhs)")->check(CLI::Range(1, 1000000));
  sweep->add_option("--sample-seed", o.sample_seed, "seed of the Latin hypercube (default: --seed)")->check(cli::Seed());
  CLI::Option* workers = sweep->add_option("--workers", o.workers, "local worker processes (default: one per core)")
                             ->check(CLI::Range(1, 4096));
  sweep->add_option("--broker", o.broker, "a running broker's client endpoint instead of local workers")
      ->check(cli::Endpoint())
      ->excludes(workers);
  return sweep;
}

// The sweep's sampling options that only go together (CLI11 cannot say "needs --sample lhs").
void CheckSampling(const CLI::App& sweep, BatchOptions& o) {
  const std::size_t samples = sweep.get_option("--samples")->count();
  o.sample_seed_given = sweep.get_option("--sample-seed")->count() > 0;
  if (o.sample == "lhs" && samples == 0) throw CLI::ValidationError("--sample lhs", "needs --samples N");
  if (o.sample != "lhs" && (samples > 0 || o.sample_seed_given)) {
    throw CLI::ValidationError(samples > 0 ? "--samples" : "--sample-seed", "needs --sample lhs");
  }
}

// run, submit, sweep and evolve: what is given (a resume tells it from defaults) and what is required without --resume.
void CheckBatchCommand(const CLI::App& command, BatchOptions& o) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() > 0) o.given.insert(option->get_name());
  }
  if (!o.resume.empty()) return;
  if (o.scenario.empty()) throw CLI::RequiredError("scenario");
  if (command.get_name() == "sweep" && o.params.empty()) throw CLI::RequiredError("--param");
}

}  // namespace

std::vector<std::string> ResumeCommandLine(const BatchOptions& options, const std::string& folder) {
  const char* command = options.command == Command::kSubmit  ? "submit"
                        : options.command == Command::kSweep ? "sweep"
                        : options.command == Command::kEvolve ? "evolve"
                                                              : "run";
  std::vector<std::string> words = {"orcs-batch", command, "--resume", folder};
  const auto given = [&](const char* option) { return options.given.count(option) != 0; };
  if (!options.broker.empty()) words.insert(words.end(), {"--broker", options.broker});
  if (given("--workers")) words.insert(words.end(), {"--workers", std::to_string(options.workers)});
  if (!options.curve_keys.empty()) words.insert(words.end(), {"--curve-keys", options.curve_keys});
  if (given("--heartbeat")) words.insert(words.end(), {"--heartbeat", text::FormatDouble(options.heartbeat_seconds)});
  return words;
}

ParsedBatchOptions ParseBatchOptions(int argc, const char* const* argv) {
  ParsedBatchOptions parsed;
  BatchOptions& o = parsed.options;
  CLI::App app{"orcs-batch: evaluates batches of genome-and-scenario jobs on local workers or a broker",
               "orcs-batch"};
  app.require_subcommand(1);
  CLI::App* run = app.add_subcommand("run", "run a batch on an embedded broker with local workers");
  AddJobOptions(*run, o, true);
  AddWorkersOption(*run, o);
  CLI::App* submit = AddSubmitCommand(app, o);
  CLI::App* sweep = AddSweepCommand(app, o);
  CLI::App* evolve = AddEvolveCommand(app, o);
  CLI::App* regress = AddRegressCommand(app, o);
  CLI::App* compare = app.add_subcommand("compare", "compare the same jobs in two runs: status, fitness and terms");
  compare->add_option("runs", o.runs, "two results.jsonl files or batch folders: A, then B")
      ->required()
      ->expected(2)
      ->check(CLI::ExistingPath);
  compare->add_option("--tolerance", o.tolerance, "a figure has changed when it moved by more than this (default 0: any bit)")
      ->check(cli::NumberIn(0.0, 1e300));
  compare->add_option("--out", o.out, "folder for compare.csv and compare.png (default runs/compare)");
  compare->add_flag("--no-plot", o.no_plot, "do not draw compare.png");
  CLI::App* resolve =
      app.add_subcommand("resolve", "print the scenario with every referenced file inlined, as jobs carry it");
  resolve->add_option("scenario", o.scenario, "the scenario file (docs/scenarios.md)")->required();
  try {
    app.parse(argc, argv);
    if (!o.genome.empty() && !o.genomes.empty()) throw CLI::ValidationError("--genome", "excludes --genomes");
    o.command = submit->parsed()    ? Command::kSubmit
                : sweep->parsed()   ? Command::kSweep
                : evolve->parsed()  ? Command::kEvolve
                : resolve->parsed() ? Command::kResolve
                : regress->parsed() ? Command::kRegress
                : compare->parsed() ? Command::kCompare
                                    : Command::kRun;
    o.seed_given = evolve->parsed() && evolve->count("--seed") > 0;
    CheckSampling(*sweep, o);
    for (CLI::App* batch : {run, submit, sweep, evolve}) {
      if (batch->parsed()) CheckBatchCommand(*batch, o);
    }
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    parsed.exit_code = cli::kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    parsed.exit_code = cli::kExitOk;
  } catch (const CLI::ParseError& error) {
    std::cerr << cli::ParseErrorLine(app, error, std::vector<std::string>(argv, argv + argc)) << "\n";
    parsed.exit_code = cli::kExitBadInput;
  }
  return parsed;
}

}  // namespace orcs::batch
