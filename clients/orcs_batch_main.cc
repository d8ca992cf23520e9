// orcs-batch: evaluates batches of genome-and-scenario jobs (docs/batch.md), and evolves genomes with them
// (`evolve`, docs/evolution.md). `run`, `sweep` and `evolve` start an embedded
// broker and local orcs-worker processes — the one-machine default with no set-up; `submit` and `sweep --broker`
// use a running broker; `resolve` prints a scenario with its files inlined; `regress` runs a suite against its
// baseline (docs/regress.md). Every input is checked before anything is submitted. Exit 0 when every job ran ok
// (regress: every case passed), 1 when some failed, 2 on bad input or when no broker answers, 130 when Ctrl-C or
// SIGTERM stopped it (clients/runtime/interrupt.h; it says how to resume).
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>
#include <unordered_set>

#include "clients/batch/batch_manifest.h"
#include "clients/batch/batch_options.h"
#include "clients/batch/latin_hypercube.h"
#include "clients/batch/robustness_report.h"
#include "clients/batch/run_comparison.h"
#include "clients/batch/sweep_grid.h"
#include "clients/batch/sweep_report.h"
#include "clients/evolve/evolve_command.h"
#include "clients/regress/regress_plan.h"
#include "clients/runtime/batch_client.h"
#include "clients/runtime/batch_input.h"
#include "clients/runtime/batch_session.h"
#include "clients/runtime/interrupt.h"
#include "clients/runtime/local_cluster.h"
#include "clients/runtime/plot_script.h"
#include "clients/runtime/progress_file.h"
#include "model/core/error.h"
#include "net/cli_style.h"
#include "net/curve_keys.h"
#include "net/status_client.h"

namespace orcs::batch {
using namespace runtime;  // orcs-batch is built on the client runtime (clients/runtime/)

namespace {

// Everything decided before anything runs.
struct Plan {
  ScenarioInput input;
  std::vector<Genome> genomes;
  std::vector<SweepAxis> axes;        // sweep only
  std::vector<SweepPoint> points;     // sweep only
  SweepSampling sampling = SweepSampling::kGrid;  // sweep only
  std::vector<PlannedJob> jobs;                   // regress only: its few cases, planned in full
  // The batch's jobs, made one at a time as the session's window has room (docs/batch.md, "Large batches"); it
  // refers to input, genomes, points and jobs above, so a Plan is never copied or moved once it is made.
  std::unique_ptr<JobSource> source;
  std::string out;
  std::optional<regress::RegressPlan> regress;  // regress only
  // --resume: the jobs of `source` without a result in the partial file, and the results that are there.
  std::unique_ptr<JobSource> remaining;
  std::vector<v1::Result> earlier_results;

  /// What this run submits: the whole batch, or what a resumed one still lacks.
  const JobSource& to_run() const { return remaining ? *remaining : *source; }
};

std::vector<Genome> GenomesOf(const BatchOptions& options, const ScenarioInput& input) {
  if (!options.genomes.empty()) return ReadGenomes(options.genomes);
  if (!options.genome.empty()) return {ParseGenomeOption(options.genome)};
  return {DefaultGenome(input)};
}

Plan MakeRegressPlan(const BatchOptions& options) {
  Plan plan;
  plan.regress = regress::PlanRegression(options, std::cerr);
  plan.jobs = std::move(plan.regress->jobs);
  plan.out = options.out.empty() ? (std::filesystem::path("runs") / plan.regress->suite.name).string() : options.out;
  return plan;
}

// Fills `plan` (in place: its source refers to its other members).
void MakePlan(const BatchOptions& options, Plan& plan) {
  if (options.command == Command::kRegress) {
    plan = MakeRegressPlan(options);
    plan.source = std::make_unique<PlannedJobList>(plan.jobs);  // here, once `plan` holds the jobs for good
    return;
  }
  plan.input = LoadScenario(options.scenario, options.engine);
  plan.genomes = GenomesOf(options, plan.input);
  const JobSettings settings{options.seed, options.jobs, options.time_limit_seconds};
  if (options.command == Command::kSweep) {
    if (options.sample == "lhs") plan.sampling = SweepSampling::kLatinHypercube;
    for (const std::string& param : options.params) plan.axes.push_back(ParseSweepAxis(param, plan.sampling));
    plan.points = plan.sampling == SweepSampling::kGrid
                      ? SweepGrid(plan.axes)
                      : LatinHypercube(plan.axes, options.samples,
                                       options.sample_seed_given ? options.sample_seed : options.seed);
    plan.source = std::make_unique<SweepJobSource>(plan.input, plan.genomes.front(), plan.points, settings);
  } else {
    plan.source = std::make_unique<RunJobSource>(plan.input, plan.genomes, settings);
  }
  if (!options.record.empty()) plan.source->Record(ParseJobSelection(options.record, plan.source->size()));
  // Everything before the first job is submitted: every job is a checked one but for its genome and seed.
  CheckJobs(plan.input, plan.genomes, *plan.source);
  plan.out = options.out.empty() ? (std::filesystem::path("runs") / plan.input.scenario.name).string() : options.out;
}

int LocalWorkerCount(const BatchOptions& options, std::size_t jobs) {
  int workers = options.workers;
  if (workers <= 0) workers = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return std::max(1, std::min(workers, static_cast<int>(std::min<std::size_t>(jobs, 4096))));
}

// progress.json's "command".
const char* CommandName(Command command) {
  switch (command) {
    case Command::kSubmit: return "submit";
    case Command::kSweep: return "sweep";
    case Command::kRegress: return "regress";
    default: return "run";
  }
}

// Runs the session against `endpoint`; prints the summary (and, for a sweep, the table).
int RunAgainst(const std::string& endpoint, const BatchOptions& options, const Plan& plan, ResultsWriter& writer) {
  runtime::BatchClientOptions client_options;
  client_options.endpoint = endpoint;
  client_options.curve_keys = options.curve_keys;
  client_options.heartbeat_interval = std::chrono::milliseconds(std::lround(options.heartbeat_seconds * 1000.0));
  client_options.batch_size = plan.source->size();  // the broker's status shows progress and time left
  runtime::BatchClient client(client_options);
  // Counts run over the whole batch (RunSession counts a resumed batch's earlier results too); the rate over
  // this session's.
  ProgressDisplay progress(std::cerr, plan.source->size(), isatty(STDERR_FILENO) != 0, ProgressDisplay::Clock::now());
  std::ostream discard(nullptr);
  ProgressDisplay quiet(discard, plan.source->size(), false, ProgressDisplay::Clock::now());
  progress.SetEarlier(plan.earlier_results.size());
  quiet.SetEarlier(plan.earlier_results.size());
  SessionOptions session;
  session.stop = &InterruptFlag();
  session.keep_results = options.command == Command::kSweep || plan.regress.has_value();
  session.earlier_results = plan.earlier_results;
  net::StatusClient status_client({endpoint, options.curve_keys, std::chrono::milliseconds(1000)});
  session.broker_status = [&status_client]() -> std::optional<v1::Status> {
    try {
      return status_client.Fetch();
    } catch (const net::StatusClientError&) {
      return std::nullopt;  // the batch client reports a lost broker itself
    }
  };
  // progress.json, for orcs-view following the run (and for the dashboard's links from a job to its replay).
  ProgressFile file(plan.out, CommandName(options.command));
  file.Set("broker_batch", client.batch_id());
  file.Set("earlier", plan.earlier_results.size());
  const auto earlier_ok = static_cast<std::size_t>(
      std::count_if(plan.earlier_results.begin(), plan.earlier_results.end(),
                    [](const v1::Result& result) { return result.status() == v1::Result::OK; }));
  file.Merge(progress.StatusJson(earlier_ok, plan.earlier_results.size() - earlier_ok, ProgressDisplay::Clock::now()));
  file.Update(ProgressDisplay::Clock::now(), true);  // a batch waiting for its first worker shows its counts
  (options.quiet ? quiet : progress).WriteTo(&file);
  const BatchSummary summary = RunSession(client, plan.to_run(), writer, options.quiet ? quiet : progress, session);
  if (summary.interrupted) {
    // What arrived is in the partial file; no report of a batch with holes (a sweep's table, a regression's
    // verdict): the resume writes them whole. The workers are stopped after this, by ~LocalCluster.
    file.Finish("interrupted");
    std::cout << SummaryText(summary, writer.results_path()) << std::flush;
    std::cerr << "orcs-batch: interrupted (Ctrl-C or SIGTERM): " << summary.ok + summary.failed << " of "
              << summary.jobs << " jobs have their result; "
              << (plan.regress ? "regress has no --resume (its few cases run again in full): run the same command "
                                 "again"
                               : "continue with: " + ShellCommand(ResumeCommandLine(options, plan.out)))
              << "\n";
    return kExitInterrupted;
  }
  writer.Finish();
  const std::string end = "finished";
  if (plan.regress) {
    const int code = regress::ReportRegression(*plan.regress, summary, writer.results_path(), std::cout);
    file.Finish(end);
    return code;
  }
  if (options.command == Command::kSweep) {
    const std::vector<SweepRow> rows = SweepRows(plan.points, *plan.source, summary.results);
    if (plan.sampling == SweepSampling::kGrid) std::cout << SweepTable(plan.axes, rows);  // lhs: in sweep.csv
    WriteSweepCsv(plan.out, plan.axes, rows);
    const RobustnessReport report = MakeRobustnessReport(plan.input.scenario.name, plan.sampling, plan.axes, rows);
    WriteRobustnessReport(plan.out, report, rows);
    std::cout << RobustnessSummary(report, rows);
    std::cout << "orcs-batch: sweep table in " << (std::filesystem::path(plan.out) / "sweep.csv").string()
              << ", robustness report in " << (std::filesystem::path(plan.out) / "robustness.md").string()
              << "; plot it with scripts/plot_sweep.py " << plan.out << "\n";
  }
  file.Finish(end);
  std::cout << SummaryText(summary, writer.results_path()) << std::flush;
  return summary.exit_code();
}

// `resolve`: the self-contained scenario text every job of the file carries (Job.scenario_json), for clients in
// other languages (clients/python) that should not repeat the resolution rules.
int PrintResolved(const BatchOptions& options) {
  std::cout << LoadScenario(options.scenario).resolved_json << "\n" << std::flush;
  return cli::kExitOk;
}

// --resume DIR: the jobs still without a result, and the results there are (docs/batch.md, "Resuming a batch").
// Returns how many bytes of the partial file hold whole lines: the rest goes.
std::uintmax_t PlanResume(Plan& plan) {
  CheckResumedInputs(plan.out, plan.input, plan.genomes);
  PartialResults partial = ReadPartialResults(plan.out);
  std::unordered_set<std::string> finished;
  for (const v1::Result& result : partial.results) finished.insert(result.job_id());
  plan.remaining = std::make_unique<RemainingJobSource>(*plan.source, finished);
  plan.earlier_results = std::move(partial.results);
  std::cerr << "orcs-batch: resuming " << plan.out << ": " << plan.earlier_results.size() << " of "
            << plan.source->size() << " jobs have their result; running the other " << plan.remaining->size()
            << "\n";
  return partial.bytes;
}

// `compare A B`: what changed, on stdout; compare.csv and compare.png in --out. Exit 0 when nothing changed, 1 when
// something did (as diff does), 2 on bad input.
int PrintComparison(const BatchOptions& options) {
  const RunComparison comparison = CompareRuns(options.runs.at(0), options.runs.at(1));
  std::cout << ComparisonText(comparison, options.tolerance);
  const std::filesystem::path out = options.out.empty() ? std::filesystem::path("runs") / "compare" : std::filesystem::path(options.out);
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) throw InputError(out.string(), 0, "cannot create the output folder: " + error.message());
  const std::string csv = (out / "compare.csv").string();
  WriteComparisonCsv(csv, comparison);
  std::cout << "orcs-batch: job by job in " << csv << "\n";
  if (!options.no_plot && RunPlotScript("plot_compare.py", {csv, "--a", comparison.a_path, "--b", comparison.b_path}, std::cout)) {
    std::cout << "orcs-batch: plotted in " << (out / "compare.png").string() << "\n";
  }
  const bool changed = !comparison.only_a.empty() || !comparison.only_b.empty() ||
                       std::any_of(comparison.common.begin(), comparison.common.end(),
                                   [&](const JobChange& change) { return Changed(change, options.tolerance); });
  return changed ? cli::kExitRunFailed : cli::kExitOk;
}

int Execute(const BatchOptions& given) {
  if (given.command == Command::kEvolve) {
    CatchInterrupts();  // the resume hint is evolve's to set, once it knows its folder
    return evolve::RunEvolve(given, &InterruptFlag());
  }
  if (given.command == Command::kResolve) return PrintResolved(given);
  if (given.command == Command::kCompare) return PrintComparison(given);
  const bool resuming = !given.resume.empty();
  const BatchOptions options = resuming ? ResumedOptions(given) : given;
  Plan plan;
  MakePlan(options, plan);
  std::uintmax_t kept_bytes = 0;
  if (resuming) kept_bytes = PlanResume(plan);
  ResultsWriter writer(plan.out, resuming ? ResultsWriter::Start::kResume : ResultsWriter::Start::kNew, kept_bytes);
  if (!resuming && !plan.regress) WriteBatchManifest(plan.out, options, plan.input, plan.genomes);
  // From here on the folder can be resumed: Ctrl-C stops in order, a second one at once (clients/runtime/interrupt.h).
  SetInterruptHint(plan.regress ? "orcs-batch: stopped at once (a second Ctrl-C); regress has no --resume: run the "
                                  "same command again"
                                : "orcs-batch: stopped at once (a second Ctrl-C); continue with: " +
                                      ShellCommand(ResumeCommandLine(options, plan.out)));
  CatchInterrupts();
  if (!options.broker.empty()) return RunAgainst(options.broker, options, plan, writer);
  LocalClusterOptions cluster_options;
  cluster_options.workers = LocalWorkerCount(options, plan.to_run().size());
  cluster_options.worker_program = WorkerProgramBesideSelf();
  cluster_options.log_path = (std::filesystem::path(plan.out) / "workers.log").string();
  cluster_options.heartbeat_interval = std::chrono::milliseconds(std::lround(options.heartbeat_seconds * 1000.0));
  cluster_options.curve_keys = options.curve_keys;
  LocalCluster cluster(cluster_options);
  if (!options.quiet) {
    std::cerr << "orcs-batch: " << plan.to_run().size() << " jobs on " << cluster_options.workers
              << " local workers (broker " << cluster.client_endpoint() << ")\n";
  }
  return RunAgainst(cluster.client_endpoint(), options, plan, writer);
}

}  // namespace
}  // namespace orcs::batch

int main(int argc, char** argv) {
  return orcs::cli::RunProgram("orcs-batch", orcs::batch::ParseBatchOptions(argc, argv), [](const auto& options) {
    try {
      return orcs::batch::Execute(options);
    } catch (const orcs::runtime::Interrupted& error) {  // how to resume has been printed where it was caught
      std::cerr << "orcs-batch: " << error.what() << "\n";
      return orcs::runtime::kExitInterrupted;
    }
  });
}
