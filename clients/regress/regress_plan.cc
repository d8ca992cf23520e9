#include "clients/regress/regress_plan.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "clients/regress/comparison.h"
#include "clients/regress/job_fingerprint.h"
#include "clients/regress/junit_report.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/scene/parameter_sets.h"

namespace orcs::regress {
namespace {

using Override = std::pair<std::string, std::string>;

void AddOverride(v1::Job& job, const Override& value) {
  v1::Override* override = job.add_overrides();
  override->set_path(value.first);
  override->set_value(value.second);
}

// The case's job: its scenario, genome and seed, its values as overrides; id = the case's name.
runtime::PlannedJob CaseJob(const SuiteCase& entry) {
  const runtime::JobSettings settings{entry.seed, 1, 0.0};
  runtime::PlannedJob planned = runtime::PlanRunJobs(entry.scenario, {entry.genome}, settings).front();
  planned.job.set_job_id(entry.name);
  for (const Override& value : entry.values) AddOverride(planned.job, value);
  planned.extra = {{"case", entry.name}, {"seed", entry.seed}};
  return planned;
}

// A --set path that the case's randomisation draws with an absolute distribution never reaches the simulation.
void NoteRedrawnPaths(const SuiteCase& entry, const std::vector<Override>& sets, std::ostream& notes) {
  for (const Override& set : sets) {
    const int i = scene::AbsoluteDrawOf(entry.scenario.scenario.randomisation, set.first);
    if (i < 0) continue;
    notes << "orcs-batch: note: case '" << entry.name << "' draws " << set.first
          << " anew for every parameter set (randomisation.parameters[" << i << "] of " << entry.scenario.path
          << "); --set does not change it there\n";
  }
}

// Checks the case's job as a worker would; an error is prefixed with the case.
void CheckCaseJob(const Suite& suite, const SuiteCase& entry, const runtime::PlannedJob& planned) {
  try {
    runtime::CheckJobs(entry.scenario, {entry.genome}, {planned});
  } catch (const InputError& error) {
    throw InputError(suite.path, 0, "case " + text::Quote(entry.name) + " (" + entry.field + "): " + error.what());
  }
}

std::vector<CaseComparison> Compare(const RegressPlan& plan, const std::map<std::string, const v1::Result*>& results) {
  std::vector<CaseComparison> comparisons;
  for (const SuiteCase& entry : plan.suite.cases) {
    const auto found = results.find(entry.name);
    const v1::Result* result = found == results.end() ? nullptr : found->second;
    comparisons.push_back(plan.update_baseline ? RecordCase(entry, result)
                                               : CompareCase(entry, *plan.baseline.Find(entry.name), result));
  }
  return comparisons;
}

Baseline NewBaseline(const RegressPlan& plan, const std::map<std::string, const v1::Result*>& results) {
  Baseline baseline;
  baseline.suite = plan.suite.name;
  for (std::size_t i = 0; i < plan.suite.cases.size(); ++i) {
    const std::string& name = plan.suite.cases[i].name;
    baseline.cases.push_back(BaselineOf(name, plan.fingerprints[i], *results.at(name)));
  }
  return baseline;
}

std::string CountLine(const std::vector<CaseComparison>& comparisons, double seconds) {
  std::map<Verdict, int> counts;
  for (const CaseComparison& comparison : comparisons) ++counts[comparison.verdict];
  char time[32];
  std::snprintf(time, sizeof time, " in %.2f s", seconds);
  std::string line = "orcs-batch regress: " + std::to_string(comparisons.size()) + " cases: ";
  if (counts[Verdict::kRecorded] > 0) line += std::to_string(counts[Verdict::kRecorded]) + " recorded, ";
  line += std::to_string(counts[Verdict::kPass]) + " pass, " + std::to_string(counts[Verdict::kRegressed]) +
          " regressed, " + std::to_string(counts[Verdict::kJobFailed]) + " failed jobs";
  if (counts[Verdict::kNoResult] > 0) line += ", " + std::to_string(counts[Verdict::kNoResult]) + " without result";
  return line + time + "\n";
}

}  // namespace

std::pair<std::string, std::string> ParseSetOption(const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos) throw InputError("--set " + text::Quote(text), 0, "expected PATH=VALUE");
  const std::string path(text::Trim(std::string_view(text).substr(0, equals)));
  const std::string value(text::Trim(std::string_view(text).substr(equals + 1)));
  if (!path.starts_with("/")) {
    throw InputError("--set " + text::Quote(text), 0, "expected a repository path starting with '/' before '='");
  }
  if (value.empty()) throw InputError("--set " + text::Quote(text), 0, "expected a value after '='");
  return {path, value};
}

RegressPlan PlanRegression(const batch::BatchOptions& options, std::ostream& notes) {
  std::vector<Override> sets;
  for (const std::string& text : options.sets) sets.push_back(ParseSetOption(text));
  if (options.update_baseline && !sets.empty()) {
    throw InputError("--set", 0, "cannot be combined with --update-baseline: a baseline records the model as it is");
  }
  RegressPlan plan;
  plan.suite = ReadSuite(options.suite);
  const std::string engine = options.engine.empty() ? "ODE" : options.engine;
  plan.baseline_path = options.baseline.empty() ? DefaultBaselinePath(options.suite, engine) : options.baseline;
  plan.update_baseline = options.update_baseline;
  plan.junit_path = options.junit;
  for (const SuiteCase& entry : plan.suite.cases) {
    runtime::PlannedJob planned = CaseJob(entry);
    // The engine is part of what a baseline records (ODE, the default, adds nothing: older baselines still match).
    if (engine != "ODE") AddOverride(planned.job, {"/Simulation/Engine", engine});
    plan.fingerprints.push_back(JobFingerprint(planned.job));
    for (const Override& set : sets) AddOverride(planned.job, set);
    plan.jobs.push_back(std::move(planned));
  }
  if (!plan.update_baseline) {
    plan.baseline = ReadBaseline(plan.baseline_path);
    CheckBaselineMatches(plan.baseline, plan.baseline_path, plan.suite, plan.fingerprints);
  }
  for (std::size_t i = 0; i < plan.suite.cases.size(); ++i) {
    CheckCaseJob(plan.suite, plan.suite.cases[i], plan.jobs[i]);
    NoteRedrawnPaths(plan.suite.cases[i], sets, notes);
  }
  return plan;
}

int ReportRegression(const RegressPlan& plan, const runtime::BatchSummary& summary, const std::string& results_path,
                     std::ostream& out) {
  std::map<std::string, const v1::Result*> results;
  for (const v1::Result& result : summary.results) results[result.job_id()] = &result;
  const std::vector<CaseComparison> comparisons = Compare(plan, results);
  out << ComparisonTable(comparisons) << CountLine(comparisons, summary.seconds);
  if (!plan.junit_path.empty()) {
    WriteJUnit(plan.junit_path, plan.suite.name, comparisons, summary.seconds);
    out << "orcs-batch regress: JUnit report in " << plan.junit_path << "\n";
  }
  out << "orcs-batch regress: results in " << results_path << "\n";
  const bool all_passed = std::all_of(comparisons.begin(), comparisons.end(),
                                      [](const CaseComparison& comparison) { return comparison.passed(); });
  if (plan.update_baseline) {
    if (!all_passed) {
      out << "orcs-batch regress: baseline not written: every case must run ok\n" << std::flush;
      return 1;
    }
    WriteBaseline(NewBaseline(plan, results), plan.baseline_path);
    out << "orcs-batch regress: baseline of " << comparisons.size() << " cases written to " << plan.baseline_path
        << "\n";
  }
  out << std::flush;
  return all_passed ? 0 : 1;
}

}  // namespace orcs::regress
