#include "clients/runtime/batch_input.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "model/control/controller_factory.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"
#include "model/evaluation/evaluation.h"
#include "model/scene/parameter_sets.h"

namespace orcs::runtime {
namespace {

using Json = nlohmann::json;

bool IsBlankOrComment(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

Genome CheckedGenome(Json value, const std::string& source, int line) {
  if (!value.is_array() && !value.is_object()) {
    throw InputError(source, line, "expected a genome (an array of numbers or a network object), found " +
                                       DescribeJson(value));
  }
  return Genome{std::move(value), source, line};
}

// "job-0007" with enough digits for `count` jobs, so that ids and log files sort in job order.
std::string NumberedId(const std::string& prefix, std::size_t index, std::size_t count) {
  const int width = static_cast<int>(std::to_string(count > 0 ? count - 1 : 0).size());
  const std::string number = std::to_string(index);
  return prefix + std::string(static_cast<std::size_t>(std::max(0, width - static_cast<int>(number.size()))), '0') +
         number;
}

v1::Job MakeJob(const ScenarioInput& input, const Genome& genome, std::uint64_t seed, const JobSettings& settings) {
  v1::Job job;
  job.set_scenario_json(input.resolved_json);
  job.set_genome_json(genome.value.dump());
  job.set_seed(seed);
  job.set_time_limit_seconds(settings.time_limit_seconds > 0 ? settings.time_limit_seconds
                                                              : scene::DefaultTimeLimitSeconds(input.scenario));
  if (input.scenario.record) {  // the scenario's "record": true — every job, set 0
    job.set_record(true);
    job.set_record_set(0);
  }
  return job;
}

std::string GenomeSource(const Genome& genome) {
  return genome.line > 0 ? genome.source + ":" + std::to_string(genome.line) : genome.source;
}

evaluation::EvaluationRequest RequestOf(const ScenarioInput& input, const Genome& genome, const v1::Job& job) {
  evaluation::EvaluationRequest request;
  request.scenario = input.scenario;
  request.genome = genome.value;
  request.seed = job.seed();
  for (const v1::Override& override : job.overrides()) {
    request.overrides.push_back({override.path(), override.value(), "override " + override.path(), 0});
  }
  return request;
}

bool SameOverrides(const v1::Job& a, const v1::Job& b) {
  if (a.overrides_size() != b.overrides_size()) return false;
  for (int i = 0; i < a.overrides_size(); ++i) {
    if (a.overrides(i).path() != b.overrides(i).path() || a.overrides(i).value() != b.overrides(i).value()) {
      return false;
    }
  }
  return true;
}

// A parameter set's absolute draw replaces the job's override of the same path, so sweeping such a path would
// change nothing; a relative draw scales the swept value and is fine.
void CheckSweptPathsAreNotRedrawn(const ScenarioInput& input, const SweepPoint& point) {
  for (const auto& [path, value] : point) {
    const int i = scene::AbsoluteDrawOf(input.scenario.randomisation, path);
    if (i < 0) continue;
    throw InputError("--param " + path, 0,
                     "the scenario's randomisation.parameters[" + std::to_string(i) +
                         "] draws this path anew for every parameter set, replacing the swept value; make that "
                         "distribution \"relative\" or remove it");
  }
}

}  // namespace

bool JobSelection::Contains(std::size_t index) const {
  if (all) return true;
  for (const auto& [first, last] : ranges) {
    if (index >= first && index <= last) return true;
  }
  return false;
}

JobSelection ParseJobSelection(const std::string& text, std::size_t job_count) {
  const auto fail = [&text](const std::string& expected) -> void {
    throw InputError("--record", 0, "expected " + expected + ", found " + text::Quote(text));
  };
  const std::string format = "'all' or job indices such as 0,3-5";
  JobSelection selection;
  if (text == "all") {
    selection.all = true;
    return selection;
  }
  if (text.empty()) fail(format);
  const auto index = [&](std::string_view digits) -> std::size_t {
    if (digits.empty() || digits.size() > 12 || digits.find_first_not_of("0123456789") != std::string_view::npos) {
      fail(format);
    }
    const std::size_t value = std::stoull(std::string(digits));
    if (value >= job_count) {
      fail(job_count == 1 ? std::string("job index 0 (the batch has 1 job)")
                          : "job indices 0…" + std::to_string(job_count - 1) + " (the batch has " +
                                std::to_string(job_count) + " jobs)");
    }
    return value;
  };
  for (std::string_view item : text::Split(text, ',')) {
    const std::size_t dash = item.find('-');
    const std::size_t first = index(item.substr(0, dash));
    const std::size_t last = dash == std::string_view::npos ? first : index(item.substr(dash + 1));
    if (last < first) fail("ranges FIRST-LAST with FIRST ≤ LAST");
    selection.ranges.emplace_back(first, last);
  }
  return selection;
}

void MarkRecorded(std::vector<PlannedJob>& jobs, const JobSelection& selection) {
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (!selection.Contains(i)) continue;
    jobs[i].job.set_record(true);
    jobs[i].job.set_record_set(0);
  }
}

std::string SweepValue::OverrideText() const { return categorical() ? text : text::FormatDouble(number); }

ScenarioInput LoadScenario(const std::string& path, const std::string& engine) {
  ScenarioInput input;
  input.path = path;
  Json resolved = scene::ResolveScenarioFile(path);
  if (!engine.empty()) scene::SetScenarioEngine(resolved, engine);
  input.scenario = scene::ParseScenario(resolved, path);
  input.resolved_json = resolved.dump();
  return input;
}

std::vector<Genome> ReadGenomes(const std::string& path) {
  std::istringstream text(ReadTextFile(path));
  std::vector<Genome> genomes;
  std::string line;
  for (int number = 1; std::getline(text, line); ++number) {
    if (IsBlankOrComment(line)) continue;
    genomes.push_back(CheckedGenome(ParseJson(line, path + ":" + std::to_string(number)), path, number));
  }
  if (genomes.empty()) throw InputError(path, 0, "expected one genome per line, found none");
  return genomes;
}

Genome ParseGenomeOption(const std::string& text) {
  if (text.starts_with("@")) {
    const std::string path = text.substr(1);
    return CheckedGenome(ParseJson(ReadTextFile(path), path), path, 0);
  }
  return CheckedGenome(ParseJson(text, "--genome"), "--genome", 0);
}

Genome DefaultGenome(const ScenarioInput& input) {
  if (input.scenario.genome.is_null()) return Genome{Json::array(), input.path + " (no genome given)", 0};
  return Genome{input.scenario.genome, input.path + " field 'genome'", 0};
}

PlannedJob JobSource::Job(std::size_t index) const {
  PlannedJob planned = Make(index);
  if (recorded_ && recorded_->Contains(index)) {
    planned.job.set_record(true);
    planned.job.set_record_set(0);
  }
  return planned;
}

std::vector<PlannedJob> AllJobs(const JobSource& source) {
  std::vector<PlannedJob> jobs;
  jobs.reserve(source.size());
  for (std::size_t i = 0; i < source.size(); ++i) jobs.push_back(source.Job(i));
  return jobs;
}

RunJobSource::RunJobSource(const ScenarioInput& input, const std::vector<Genome>& genomes,
                           const JobSettings& settings)
    : input_(input), genomes_(genomes), settings_(settings),
      repeats_(static_cast<std::size_t>(std::max(0, settings.repeats))) {}

PlannedJob RunJobSource::Make(std::size_t index) const {
  const std::size_t g = index / repeats_;
  const std::size_t r = index % repeats_;
  PlannedJob planned;
  const std::uint64_t seed = settings_.seed + static_cast<std::uint64_t>(r);
  planned.job = MakeJob(input_, genomes_.at(g), seed, settings_);
  planned.job.set_job_id(NumberedId("job-", index, size()));
  planned.extra["seed"] = seed;
  planned.extra["genome_index"] = g;
  planned.genome = static_cast<int>(g);
  return planned;
}

SweepJobSource::SweepJobSource(const ScenarioInput& input, const Genome& genome,
                               const std::vector<SweepPoint>& points, const JobSettings& settings)
    : input_(input), genome_(genome), points_(points), settings_(settings),
      repeats_(static_cast<std::size_t>(std::max(0, settings.repeats))) {
  if (!points.empty()) CheckSweptPathsAreNotRedrawn(input, points.front());
}

std::vector<std::size_t> SweepJobSource::Representatives() const {
  std::vector<std::size_t> indices;
  if (repeats_ == 0) return indices;
  for (std::size_t p = 0; p < points_.size(); ++p) indices.push_back(p * repeats_);
  return indices;
}

PlannedJob SweepJobSource::Make(std::size_t index) const {
  const std::size_t p = index / repeats_;
  const std::size_t r = index % repeats_;
  nlohmann::ordered_json point = nlohmann::ordered_json::object();
  for (const auto& [path, value] : points_.at(p)) {
    point[path] = value.categorical() ? nlohmann::ordered_json(value.text) : nlohmann::ordered_json(value.number);
  }
  PlannedJob planned;
  const std::uint64_t seed = settings_.seed + static_cast<std::uint64_t>(r);
  planned.job = MakeJob(input_, genome_, seed, settings_);
  planned.job.set_job_id(NumberedId("point-", p, points_.size()) + "-r" + std::to_string(r));
  for (const auto& [path, value] : points_[p]) {
    v1::Override* override = planned.job.add_overrides();
    override->set_path(path);
    override->set_value(value.OverrideText());
  }
  planned.extra["seed"] = seed;
  planned.extra["point"] = p;
  planned.extra["params"] = point;
  return planned;
}

RemainingJobSource::RemainingJobSource(const JobSource& source, const std::unordered_set<std::string>& finished)
    : source_(source) {
  for (std::size_t i = 0; i < source.size(); ++i) {
    if (finished.count(source.Job(i).job.job_id()) == 0) remaining_.push_back(i);
  }
}

std::vector<std::size_t> PlannedJobList::Representatives() const {
  std::vector<std::size_t> indices(jobs_.size());
  for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = i;
  return indices;
}

std::vector<PlannedJob> PlanRunJobs(const ScenarioInput& input, const std::vector<Genome>& genomes,
                                    const JobSettings& settings) {
  return AllJobs(RunJobSource(input, genomes, settings));
}

std::vector<PlannedJob> PlanSweepJobs(const ScenarioInput& input, const Genome& genome,
                                      const std::vector<SweepPoint>& points, const JobSettings& settings) {
  return AllJobs(SweepJobSource(input, genome, points, settings));
}

void CheckJobs(const ScenarioInput& input, const std::vector<Genome>& genomes, const std::vector<PlannedJob>& jobs) {
  CheckJobs(input, genomes, PlannedJobList(jobs));
}

void CheckJobs(const ScenarioInput& input, const std::vector<Genome>& genomes, const JobSource& source) {
  if (source.size() == 0) return;
  // The controller first, under the scenario's name (a bad "controller" is the scenario's error, not a genome's);
  // then the genomes, so that a genome's error names its file and line rather than the scenario.
  const control::ControlTarget target = evaluation::ControlTargetOf(input.scenario);
  control::CheckController(input.scenario.controller, target, input.path);
  for (const Genome& genome : genomes) {
    control::CheckGenome(input.scenario.controller, genome.value, target, GenomeSource(genome));
  }
  const PlannedJob first = source.Job(0);
  evaluation::CheckRequest(RequestOf(input, genomes.at(first.genome), first.job));
  for (const std::size_t index : source.Representatives()) {
    if (index == 0) continue;
    const PlannedJob planned = source.Job(index);
    if (!SameOverrides(planned.job, first.job)) {
      evaluation::CheckRequest(RequestOf(input, genomes.at(planned.genome), planned.job));
    }
  }
}

}  // namespace orcs::runtime
