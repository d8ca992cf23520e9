#include "clients/evolve/evolve_command.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "clients/evolve/evolution.h"
#include "clients/evolve/evolution_checkpoint.h"
#include "clients/evolve/evolution_report.h"
#include "clients/evolve/evolution_settings.h"
#include "clients/runtime/batch_input.h"
#include "clients/runtime/interrupt.h"
#include "clients/runtime/job_runner.h"
#include "clients/runtime/local_cluster.h"
#include "clients/runtime/plot_script.h"
#include "clients/runtime/progress_display.h"
#include "clients/runtime/progress_file.h"
#include "clients/runtime/results_writer.h"
#include "model/core/error.h"
#include "model/core/text.h"


namespace orcs::evolve {
namespace {

namespace fs = std::filesystem;

EvolutionOverrides OverridesOf(const batch::BatchOptions& options) {
  EvolutionOverrides overrides;
  overrides.algorithm = options.algorithm;
  overrides.population = options.population;
  overrides.generations = options.generations;
  if (options.seed_given) overrides.seed = static_cast<std::int64_t>(options.seed);
  overrides.validate = options.validate;
  overrides.fresh_sets = options.fresh_sets;
  return overrides;
}

// --resume DIR continues in DIR (the command line refuses --out with it); otherwise --out DIR, by default
// runs/<scenario name>-evolve.
std::string OutputFolder(const batch::BatchOptions& options, const runtime::ScenarioInput& input) {
  if (!options.resume.empty()) {
    return options.resume;
  }
  const std::string folder =
      options.out.empty() ? (fs::path("runs") / (input.scenario.name + "-evolve")).string() : options.out;
  if (fs::exists(fs::path(folder) / "checkpoint.json")) {
    throw InputError(folder + " holds an evolution run already (checkpoint.json): continue it with --resume " + folder +
                     ", or give another --out");
  }
  return folder;
}

runtime::Genome GenomeJson(const std::vector<double>& genes, const std::string& source) {
  return {nlohmann::json(genes), source, 0};
}

// One job per genome, all with one seed (the generation's): every genome of a generation meets the same parameter
// sets (a fair comparison).
std::vector<v1::Job> JobsOf(const runtime::ScenarioInput& input, const std::vector<std::vector<double>>& genomes,
                            std::uint64_t seed, double time_limit_seconds) {
  std::vector<runtime::Genome> list;
  for (const std::vector<double>& genes : genomes) list.push_back(GenomeJson(genes, "evolve"));
  std::vector<v1::Job> jobs;
  for (runtime::PlannedJob& planned : runtime::PlanRunJobs(input, list, {seed, 1, time_limit_seconds})) {
    planned.job.clear_record();  // a scenario's "record": true is for batches; evolve records only its winner
    planned.job.clear_record_set();
    jobs.push_back(std::move(planned.job));
  }
  return jobs;
}

// Checks the scenario's jobs as a worker would (world, parameter sets, controller, fitness) before any is sent.
void CheckBeforeSubmitting(const runtime::ScenarioInput& input, const EvolutionSettings& settings,
                           double time_limit_seconds) {
  std::vector<double> genes = settings.start;
  if (genes.empty()) {
    for (const GeneBounds& b : settings.bounds) genes.push_back(0.5 * (b.low + b.high));
  }
  const std::vector<runtime::Genome> genomes = {GenomeJson(genes, "evolution.bounds")};
  runtime::CheckJobs(input, genomes, runtime::PlanRunJobs(input, genomes, {settings.seed, 1, time_limit_seconds}));
}

// Four significant digits, as the generation lines print fitness.
std::string Short(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// Progress inside a generation (issue 21: a generation used to be a minute of silence): on a terminal one line
// redrawn with the jobs done and the best and median fitness so far, replaced by the generation's summary line when
// it ends; elsewhere (a log, CI) a plain line at most every 10 s.
class GenerationProgress {
 public:
  /// `shown`: on stderr; `file`: progress.json, kept up to date whether shown or not.
  GenerationProgress(bool shown, int generations, runtime::ProgressFile& file)
      : shown_(shown), generations_(generations), file_(file) {
    file_.Set("generations", generations_);
  }

  /// The next generation's number (after a resume).
  void SetGeneration(int generation) { generation_ = generation; }
  /// A generation of `jobs` jobs begins.
  void Start(std::size_t jobs) {
    fitness_.clear();
    ok_ = failed_ = 0;
    display_ = std::make_unique<runtime::ProgressDisplay>(shown_ ? std::cerr : discard_, jobs,
                                                        shown_ && isatty(STDERR_FILENO) != 0,
                                                        runtime::ProgressDisplay::Clock::now());
    display_->SetLabel("generation " + std::to_string(generation_) + "/" + std::to_string(generations_) + ": ");
    display_->WriteTo(&file_);
    file_.Set("generation", generation_);
    file_.Set("best_so_far", nullptr);
    file_.Set("median_so_far", nullptr);
    const auto now = runtime::ProgressDisplay::Clock::now();
    file_.Merge(display_->StatusJson(0, 0, now));  // the page shows the generation from its start
    file_.Update(now, true);
  }
  void OnResult(const v1::Result& result) {
    if (result.status() == v1::Result::OK) {
      ++ok_;
      fitness_.push_back(result.fitness());
    } else {
      ++failed_;
    }
    if (!fitness_.empty()) {
      std::vector<double> sorted = fitness_;
      std::sort(sorted.begin(), sorted.end());
      display_->SetDetail("; best " + Short(sorted.back()) + ", median " + Short(sorted[sorted.size() / 2]) +
                          " in this generation so far");
      file_.Set("best_so_far", sorted.back());
      file_.Set("median_so_far", sorted[sorted.size() / 2]);
    }
    display_->Update(ok_, failed_, runtime::ProgressDisplay::Clock::now());
  }
  /// Ctrl-C: the generation under way (if one is) will not end; its progress line gives way to a line saying so.
  void Abandon() {
    if (display_ && shown_) display_->Notice("generation " + std::to_string(generation_) + ": abandoned");
    display_.reset();
  }
  /// The generation's summary line, in place of the progress line; fitness.csv has the generation now.
  void Finish(const std::string& line) {
    if (shown_) {
      if (display_) {
        display_->Notice(line);
      } else {
        std::cerr << line << "\n";
      }
    }
    if (display_) file_.Merge(display_->StatusJson(ok_, failed_, runtime::ProgressDisplay::Clock::now()));
    file_.Set("last_generation", generation_);  // fitness.csv holds generations 0 to this
    file_.Update(runtime::ProgressDisplay::Clock::now(), true);
    display_.reset();
    ++generation_;
  }

 private:
  const bool shown_;
  const int generations_;
  runtime::ProgressFile& file_;
  std::ostream discard_{nullptr};  ///< where an unshown display writes: nowhere
  int generation_ = 0;
  std::unique_ptr<runtime::ProgressDisplay> display_;
  std::vector<double> fitness_;
  std::size_t ok_ = 0, failed_ = 0;
};

GenomeEvaluator BrokerEvaluator(runtime::JobRunner& runner, const runtime::ScenarioInput& input, double time_limit_seconds,
                                GenerationProgress& progress) {
  return [&runner, &input, time_limit_seconds, &progress](const std::vector<std::vector<double>>& genomes,
                                                          std::uint64_t seed) {
    progress.Start(genomes.size());
    const std::vector<v1::Result> results = runner.Run(
        JobsOf(input, genomes, seed, time_limit_seconds), [&](const v1::Result& result) { progress.OnResult(result); });
    std::vector<Evaluation> evaluations;
    for (const v1::Result& result : results) {
      evaluations.push_back({result.fitness(), result.status() == v1::Result::OK});
    }
    return evaluations;
  };
}

runtime::RunnerOptions RunnerOptionsOf(const batch::BatchOptions& options, const std::string& folder,
                                     const std::atomic<bool>* stop) {
  runtime::RunnerOptions runner;
  runner.stop = stop;
  runner.broker = options.broker;
  runner.workers = options.workers;
  runner.log_path = (fs::path(folder) / "workers.log").string();
  runner.curve_keys = options.curve_keys;
  runner.heartbeat_interval = std::chrono::milliseconds(std::lround(options.heartbeat_seconds * 1000.0));
  return runner;
}

// --resume DIR: what the command line does not give comes from the checkpoint — the scenario file, engine, time
// limit, generations, validation seeds, algorithm, population and seed (docs/evolution.md, "Resuming"). What it
// does give must agree with the checkpoint's fingerprint (ReadCheckpoint refuses it otherwise), but for
// --generations, which may extend the run.
batch::BatchOptions WithCheckpointSettings(const batch::BatchOptions& given) {
  const nlohmann::ordered_json stored = ReadCheckpointSettings(given.resume);
  const nlohmann::ordered_json& fingerprint = stored["fingerprint"];
  const nlohmann::ordered_json& run = stored["run"];
  const auto absent = [&](const char* option) { return given.given.count(option) == 0; };
  batch::BatchOptions options = given;
  if (absent("scenario")) {
    if (!run.contains("scenario_path")) {
      throw InputError("--resume " + given.resume +
                       ": its checkpoint is from an orcs-batch that did not record the scenario file; give it: "
                       "orcs-batch evolve SCENARIO.json --resume " + given.resume);
    }
    options.scenario = run["scenario_path"].get<std::string>();
  }
  try {
    if (absent("--engine") && run.contains("engine")) options.engine = run["engine"].get<std::string>();
    if (absent("--time-limit") && run.contains("time_limit_seconds")) {
      options.time_limit_seconds = run["time_limit_seconds"].get<double>();
    }
    if (absent("--generations") && run.contains("generations")) options.generations = run["generations"].get<int>();
    if (absent("--validate") && run.contains("validate")) options.validate = run["validate"].get<int>();
    if (absent("--algorithm")) options.algorithm = fingerprint.value("algorithm", "");
    if (absent("--population")) options.population = fingerprint.value("population", 0);
    if (absent("--fresh-sets")) options.fresh_sets = fingerprint.value("fresh_sets", false);
    if (absent("--seed") && fingerprint.contains("seed")) {
      options.seed = fingerprint["seed"].get<std::uint64_t>();
      options.seed_given = true;
    }
  } catch (const nlohmann::json::exception& error) {
    throw InputError((fs::path(given.resume) / "checkpoint.json").string(), 0,
                     std::string("damaged run settings: ") + error.what());
  }
  return options;
}

void SaveGeneration(const std::string& folder, const Evolution& evolution, const nlohmann::ordered_json& fingerprint,
                    const nlohmann::ordered_json& run) {
  WriteCheckpoint(folder, CheckpointOf(evolution, fingerprint, run));
  WriteFitnessCsv(folder, evolution.history());
  WriteBestGenome(folder, evolution.champion());
}

// DIR/best/: the winner once more with the seed it was scored with (its logs and its recording, best/recordings/winner.orcsrec for
// orcs-view, of parameter set 0; it must give the same fitness, bit for bit: recording changes no bits) and on
// `validate` fresh seeds (how it fares on parameter sets it never met). Returns false when the replay differs.
bool WriteWinner(runtime::JobRunner& runner, const runtime::ScenarioInput& input, const EvolutionSettings& settings,
                 const Champion& champion, double time_limit_seconds, const std::string& folder) {
  std::vector<v1::Job> jobs = JobsOf(input, {champion.genome}, champion.seed, time_limit_seconds);
  jobs.front().set_record(true);
  jobs.front().set_record_set(0);
  for (int v = 1; v <= settings.validate; ++v) {
    std::vector<v1::Job> more =
        JobsOf(input, {champion.genome}, settings.seed + static_cast<std::uint64_t>(v), time_limit_seconds);
    jobs.push_back(std::move(more.front()));
  }
  std::vector<v1::Result> results = runner.Run(std::move(jobs));
  runtime::ResultsWriter writer((fs::path(folder) / "best").string());
  std::vector<double> validation;
  for (std::size_t i = 0; i < results.size(); ++i) {
    results[i].set_job_id(i == 0 ? "winner" : "validate-" + std::to_string(i));
    writer.Write(results[i], {{"seed", i == 0 ? champion.seed : settings.seed + i},
                              {"role", i == 0 ? "winner" : "validation"}});
    if (i > 0 && results[i].status() == v1::Result::OK) validation.push_back(results[i].fitness());
  }
  writer.Finish();
  const v1::Result& replay = results.front();
  const bool same = replay.status() == v1::Result::OK && replay.fitness() == champion.fitness;
  std::cout << "orcs-batch: winner (generation " << champion.generation << ") fitness "
            << text::FormatDouble(champion.fitness) << "; replayed: " << text::FormatDouble(replay.fitness())
            << (same ? " (the same bits)" : " — DIFFERENT: the evaluation is not reproducible") << "\n";
  if (!validation.empty()) {
    double sum = 0.0, lowest = validation.front();
    for (double f : validation) {
      sum += f;
      lowest = std::min(lowest, f);
    }
    std::cout << "orcs-batch: on " << validation.size() << " fresh seeds (" << settings.seed + 1 << "…"
              << settings.seed + settings.validate << "): mean fitness "
              << text::FormatDouble(sum / static_cast<double>(validation.size())) << ", lowest "
              << text::FormatDouble(lowest) << "\n";
  }
  return same;
}

}  // namespace

int RunEvolve(const batch::BatchOptions& given, const std::atomic<bool>* stop) {
  if (given.resume.empty() && given.scenario.empty()) throw InputError("evolve: the scenario file is required");
  const batch::BatchOptions options = given.resume.empty() ? given : WithCheckpointSettings(given);
  const runtime::ScenarioInput input = runtime::LoadScenario(options.scenario, options.engine);
  const EvolutionSettings settings = ReadEvolutionSettings(input, OverridesOf(options));
  const std::string folder = OutputFolder(options, input);
  const nlohmann::ordered_json fingerprint = Fingerprint(input, settings);
  const nlohmann::ordered_json run = RunSettings(options.scenario, options.engine, settings.generations,
                                                 settings.validate, options.time_limit_seconds);
  std::optional<EvolutionCheckpoint> checkpoint;
  if (!options.resume.empty()) {
    CheckResumable(settings.algorithm, "--resume " + folder);
    checkpoint = ReadCheckpoint(folder, fingerprint);
  }
  CheckBeforeSubmitting(input, settings, options.time_limit_seconds);
  fs::create_directories(folder);

  // Ctrl-C from here on (clients/runtime/interrupt.h): the generation under way is abandoned — a checkpoint holds
  // only whole generations, and the resume runs that one again, to the same bits — and the command says how to
  // continue; a second Ctrl-C exits at once.
  const std::string resume = runtime::ShellCommand(batch::ResumeCommandLine(options, folder));
  const auto hint_resume = [&] {
    runtime::SetInterruptHint("orcs-batch: stopped at once (a second Ctrl-C); continue with: " + resume);
  };
  if (checkpoint) {
    hint_resume();
  } else {
    runtime::SetInterruptHint("orcs-batch: stopped at once (a second Ctrl-C) in generation 0, before the first "
                            "checkpoint: nothing to resume; run the same command again");
  }

  runtime::JobRunner runner(RunnerOptionsOf(options, folder, stop));
  runtime::ProgressFile file(folder, "evolve");
  GenerationProgress progress(!options.quiet, settings.generations, file);
  Evolution evolution(settings, BrokerEvaluator(runner, input, options.time_limit_seconds, progress));
  if (!options.quiet) {
    std::cerr << "orcs-batch: evolving '" << input.scenario.name << "' (" << settings.bounds.size() << " genes) with "
              << AlgorithmName(settings.algorithm) << ", " << settings.population << " genomes per generation, on "
              << (options.broker.empty() ? std::to_string(runner.local_workers()) + " local workers"
                                         : "broker " + options.broker)
              << "; output in " << folder << "\n";
  }
  bool saved = checkpoint.has_value();  // the folder holds a checkpoint: it can be resumed
  // What Ctrl-C prints, once the step under way is abandoned (`abandoned`: what it was).
  const auto interrupted = [&](const std::string& abandoned) {
    progress.Abandon();
    file.Finish("interrupted");
    if (!saved) {
      std::cerr << "orcs-batch: interrupted (Ctrl-C or SIGTERM) in generation 0, before the first checkpoint: "
                   "nothing to resume; run the same command again\n";
    } else {
      std::cerr << "orcs-batch: interrupted (Ctrl-C or SIGTERM) after generation " << evolution.generation()
                << abandoned << "; continue with: " << resume << "\n";
    }
    return runtime::kExitInterrupted;
  };
  try {
    if (checkpoint) {
      evolution.Restore(checkpoint->pagmo_state, checkpoint->history, checkpoint->champion,
                        (fs::path(folder) / "checkpoint.json").string());
      if (!options.quiet) std::cerr << "orcs-batch: resuming after generation " << evolution.generation() << "\n";
      progress.SetGeneration(evolution.generation() + 1);
    } else {
      evolution.Initialise();
      SaveGeneration(folder, evolution, fingerprint, run);
      saved = true;
      hint_resume();
      progress.Finish(GenerationLine(evolution.history().back(), settings.generations));
    }
    while (evolution.generation() < settings.generations && !(stop != nullptr && stop->load())) {
      evolution.Step();
      SaveGeneration(folder, evolution, fingerprint, run);
      progress.Finish(GenerationLine(evolution.history().back(), settings.generations));
    }
  } catch (const runtime::Interrupted&) {
    return interrupted(" (generation " + std::to_string(evolution.generation() + 1) +
                       ", under way, is abandoned: the resume runs it again, to the same bits)");
  }
  if (evolution.generation() < settings.generations) return interrupted("");
  if (evolution.champion().genome.empty()) {
    std::cout << "orcs-batch: no genome ran ok in " << evolution.generation() + 1 << " generations (see "
              << (fs::path(folder) / "workers.log").string() << ")\n";
    return 1;
  }
  file.Set("label", "replaying the winner");
  file.Update(runtime::ProgressDisplay::Clock::now(), true);
  bool reproducible = false;
  try {
    reproducible = WriteWinner(runner, input, settings, evolution.champion(), options.time_limit_seconds, folder);
  } catch (const runtime::Interrupted&) {
    return interrupted(", the last, while its winner was replayed (the resume replays it)");
  }
  if (!options.no_plot) runtime::RunPlotScript("plot_evolution.py", {folder}, std::cout);  // fitness.png
  file.Set("label", nullptr);
  file.Finish("finished");
  std::cout << "orcs-batch: best genome in " << (fs::path(folder) / "best_genome.json").string()
            << "; replay it with: orcs-sim --scenario " << options.scenario << " --genome @"
            << (fs::path(folder) / "best_genome.json").string() << " --seed " << evolution.champion().seed
            << (options.engine.empty() ? "" : " --engine " + options.engine) << "\n";
  if (fs::exists(fs::path(folder) / "best" / "recordings" / "winner.orcsrec")) {
    std::cout << "orcs-batch: watch the winner with: orcs-view " << folder << "\n";
  }
  if (evolution.cache_misses() > 0) {
    std::cout << "orcs-batch: " << evolution.cache_misses() << " genomes were evaluated outside their generation's "
              << "batch (the algorithm looked at answers mid-generation)\n";
  }
  return reproducible ? 0 : 1;
}

}  // namespace orcs::evolve
