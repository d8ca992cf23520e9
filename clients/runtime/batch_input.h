// What orcs-batch reads before it submits anything: the scenario file (resolved, so the jobs carry every file
// they need), genomes, and the jobs built from them. Everything is checked here, with the file and field named,
// so bad input is an error before submission (exit 2), never a batch of failed jobs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "model/scene/scenario.h"
#include "orcs/v1/job.pb.h"

namespace orcs::runtime {

/// A scenario file, read and resolved.
struct ScenarioInput {
  std::string path;           ///< the file as given on the command line
  std::string resolved_json;  ///< the scenario with every referenced file inlined: what each job carries
  scene::Scenario scenario;   ///< parsed from resolved_json
};

/// Reads, resolves and parses a scenario file, its world put on `engine` unless that is "" (--engine). Throws
/// InputError naming the file and field.
ScenarioInput LoadScenario(const std::string& path, const std::string& engine = "");

/// One genome with where it came from, for messages ("genomes.jsonl:3", "--genome", "scenario 'genome'").
struct Genome {
  nlohmann::json value;  ///< a flat array of numbers or a full network object
  std::string source;    ///< where it was read
  int line = 0;          ///< 1-based line in `source`, 0 when it has none
};

/// The genomes of a JSON-lines file: one genome per non-blank line ('#' lines are comments). Throws InputError
/// "FILE:LINE: ..." for a line that is not JSON or not an array or object, and for a file without genomes.
std::vector<Genome> ReadGenomes(const std::string& path);

/// A genome given as JSON text on the command line (or "@FILE" for a file holding one). Throws InputError.
Genome ParseGenomeOption(const std::string& text);

/// The jobs `--record JOBS` names: "all", or comma-separated 0-based job indices and ranges such as "0,3-5" (a
/// range includes both ends), in the order the batch plans its jobs.
struct JobSelection {
  bool all = false;
  std::vector<std::pair<std::size_t, std::size_t>> ranges;  ///< [first, last], each first ≤ last
  bool Contains(std::size_t index) const;
};

/// A job to submit, with what results.jsonl adds to its line.
struct PlannedJob {
  v1::Job job;                   ///< complete but for batch_id (the client library sets it)
  nlohmann::ordered_json extra;  ///< merged into the job's results.jsonl line: seed, genome index, sweep point
  int genome = 0;                ///< index of its genome in the list the plan was made from
};

/// How the jobs of a batch are made.
struct JobSettings {
  std::uint64_t seed = 1;            ///< seed of the first repeat; repeat r uses seed + r
  int repeats = 1;                   ///< jobs per genome (or per sweep point), ≥ 1, each with its own seed
  double time_limit_seconds = 0.0;   ///< per job, wall clock; 0 = scene::DefaultTimeLimitSeconds of the scenario
};

/// The jobs of `orcs-batch run`: every genome × every repeat, ids "job-0000", "job-0001", ... in that order.
/// Genome g, repeat r gets seed settings.seed + r (every genome meets the same parameter sets: fair comparison).
std::vector<PlannedJob> PlanRunJobs(const ScenarioInput& input, const std::vector<Genome>& genomes,
                                    const JobSettings& settings);

/// One swept value: a number, or one category of a categorical axis (e.g. a floor material).
struct SweepValue {
  double number = 0.0;  ///< the value in the path's unit; for a category, its index on the axis (from 0)
  std::string text;     ///< the category as the repository reads it, e.g. "Wood"; "" for a number
  SweepValue(double value = 0.0) : number(value) {}  // NOLINT(google-explicit-constructor): grid points are numbers
  SweepValue(std::string category, int index) : number(index), text(std::move(category)) {}
  bool categorical() const { return !text.empty(); }
  /// What a job's override carries: the category, or the number in its shortest exact form.
  std::string OverrideText() const;
  bool operator==(const SweepValue&) const = default;
};

/// One point of a sweep: repository path → value, in axis order.
using SweepPoint = std::vector<std::pair<std::string, SweepValue>>;

/// The jobs of `orcs-batch sweep`: every point × every repeat, one genome, the point's values as overrides; ids
/// "point-0000-r0", ...; every point uses the same seeds (settings.seed + r). Throws InputError when the scenario's
/// randomisation draws a swept path with an absolute distribution (it would replace the swept value).
std::vector<PlannedJob> PlanSweepJobs(const ScenarioInput& input, const Genome& genome,
                                      const std::vector<SweepPoint>& points, const JobSettings& settings);

/// The jobs of a batch, made one at a time from their index, so that a batch of a million jobs never holds a
/// million jobs (each carries its scenario's text) in memory: everything a job holds — its genome, seed, sweep point,
/// id and whether it is recorded — follows from its index and from inputs read once. RunSession submits a window
/// of them at a time (clients/runtime/batch_session.h).
class JobSource {
 public:
  virtual ~JobSource() = default;
  /// How many jobs the batch has.
  virtual std::size_t size() const = 0;
  /// Job `index` (0 ≤ index < size()), the same every time it is asked for.
  PlannedJob Job(std::size_t index) const;
  /// The jobs whose check (CheckJobs) covers every job: every job is one of these but for its genome and seed, and
  /// every genome is checked on its own. In order, the first is job 0.
  virtual std::vector<std::size_t> Representatives() const = 0;
  /// Records parameter set 0 of every job `selection` names (as MarkRecorded).
  void Record(JobSelection selection) { recorded_ = std::move(selection); }

 protected:
  virtual PlannedJob Make(std::size_t index) const = 0;

 private:
  std::optional<JobSelection> recorded_;
};

/// The jobs of `orcs-batch run`, lazily: genome g, repeat r is job g·repeats + r (as PlanRunJobs). Keeps references
/// to `input` and `genomes`, which must outlive it.
class RunJobSource : public JobSource {
 public:
  RunJobSource(const ScenarioInput& input, const std::vector<Genome>& genomes, const JobSettings& settings);
  std::size_t size() const override { return genomes_.size() * repeats_; }
  std::vector<std::size_t> Representatives() const override { return {0}; }

 protected:
  PlannedJob Make(std::size_t index) const override;

 private:
  const ScenarioInput& input_;
  const std::vector<Genome>& genomes_;
  JobSettings settings_;
  std::size_t repeats_;
};

/// The jobs of `orcs-batch sweep`, lazily: point p, repeat r is job p·repeats + r (as PlanSweepJobs). Keeps
/// references to `input`, `genome` and `points`, which must outlive it. Throws InputError as PlanSweepJobs.
class SweepJobSource : public JobSource {
 public:
  SweepJobSource(const ScenarioInput& input, const Genome& genome, const std::vector<SweepPoint>& points,
                 const JobSettings& settings);
  std::size_t size() const override { return points_.size() * repeats_; }
  /// Repeat 0 of every point: the points' overrides differ.
  std::vector<std::size_t> Representatives() const override;

 protected:
  PlannedJob Make(std::size_t index) const override;

 private:
  const ScenarioInput& input_;
  const Genome genome_;  ///< a copy: one genome is small, and a reference to a temporary dangled
  const std::vector<SweepPoint>& points_;
  JobSettings settings_;
  std::size_t repeats_;
};

/// Jobs planned in full beforehand (regress suites: a handful of cases, each with its own scenario).
class PlannedJobList : public JobSource {
 public:
  explicit PlannedJobList(const std::vector<PlannedJob>& jobs) : jobs_(jobs) {}
  std::size_t size() const override { return jobs_.size(); }
  /// Every job: they may all differ.
  std::vector<std::size_t> Representatives() const override;

 protected:
  PlannedJob Make(std::size_t index) const override { return jobs_.at(index); }

 private:
  const std::vector<PlannedJob>& jobs_;
};

/// The jobs of `source` that have no result yet (`--resume`): those whose ids are not in `finished`, in their
/// order. Each keeps its index in `source` (its seed, point and recording follow from it). Keeps a reference to
/// `source`, which must outlive it.
class RemainingJobSource : public JobSource {
 public:
  RemainingJobSource(const JobSource& source, const std::unordered_set<std::string>& finished);
  std::size_t size() const override { return remaining_.size(); }
  /// Not needed: the whole source was checked.
  std::vector<std::size_t> Representatives() const override { return {}; }

 protected:
  PlannedJob Make(std::size_t index) const override { return source_.Job(remaining_.at(index)); }

 private:
  const JobSource& source_;
  std::vector<std::size_t> remaining_;  ///< indices into source_
};

/// Every job of `source`, in order (for small batches and tests).
std::vector<PlannedJob> AllJobs(const JobSource& source);

/// Checks the jobs as a worker would, without simulating: every genome against the controller (an error names
/// the genome's file and line), then the first job fully (evaluation::CheckRequest: world, overrides, parameter
/// sets, controller, fitness, log), then every job whose overrides differ from the first's. Throws the first
/// InputError.
void CheckJobs(const ScenarioInput& input, const std::vector<Genome>& genomes, const std::vector<PlannedJob>& jobs);

/// CheckJobs for a source, without making its jobs: the controller and every genome, then each of the source's
/// Representatives() fully. Every other job differs from one of them only in genome and seed, both checked, so
/// a batch that passes has no bad job left to find once it runs. Throws the first InputError.
void CheckJobs(const ScenarioInput& input, const std::vector<Genome>& genomes, const JobSource& source);

/// Parses `--record`'s text for a batch of `job_count` jobs. Throws InputError "--record: expected ..., found ..."
/// for anything else, an index beyond the batch's last job, or a range whose end lies before its start.
JobSelection ParseJobSelection(const std::string& text, std::size_t job_count);

/// Asks a recording of parameter set 0 of every job `selection` names (Job.record; the scenario's "record": true
/// asks it of every job already).
void MarkRecorded(std::vector<PlannedJob>& jobs, const JobSelection& selection);

/// The genomes to use when none is given on the command line: the scenario's "genome", else an empty one (a
/// controller without genes, e.g. a keyframe player).
Genome DefaultGenome(const ScenarioInput& input);

}  // namespace orcs::runtime
