// `orcs-batch compare A B` (docs/batch.md, "Comparing two runs"): the same jobs in two results files — two
// engines, two builds, before and after a model change — job by job: status, fitness and every fitness term,
// what changed and by how much.
#pragma once

#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace orcs::batch {

/// One job's figures in one run.
struct JobFigures {
  std::string status;                    ///< "ok", "timeout", ...
  std::optional<double> fitness;         ///< absent unless ok
  std::map<std::string, double> terms;   ///< each term's mean over the parameter sets
};

/// A job in both runs.
struct JobChange {
  std::string job;  ///< its id ("job-03 = job-003" when the two runs name it differently)
  JobFigures a;     ///< in the first run
  JobFigures b;     ///< in the second
};

struct RunComparison {
  std::string a_path, b_path;           ///< the results files read
  std::vector<JobChange> common;        ///< jobs in both, in the first run's order
  std::vector<std::string> only_a;      ///< job ids only in the first run
  std::vector<std::string> only_b;      ///< job ids only in the second
  std::vector<std::string> terms;       ///< every term name, in first-seen order
  std::string matched_by;               ///< "seed and genome", or "job id" where a line lacks its seed
};

/// The results file of `path`: the file itself, or a folder's results.jsonl (its .partial while a batch runs).
std::string ResultsFileOf(const std::string& path);

/// Reads both runs and pairs their jobs by what they ran — seed, genome index, sweep point (ids are zero-padded by
/// the batch's size, so the same seeds in an 8-job and a 16-job run share no id) — or by id where a line has no seed
/// or two jobs of a run ran the same. Throws InputError naming the file and line of a line that is not a result.
RunComparison CompareRuns(const std::string& a, const std::string& b);

/// Whether the job's status, fitness or a term differs by more than `tolerance` (0: any bit differs).
bool Changed(const JobChange& change, double tolerance);

/// The report: a summary (jobs in both, changed, only in one run, largest fitness change), then a table of the
/// changed jobs with each differing figure as A → B (Δ).
std::string ComparisonText(const RunComparison& comparison, double tolerance);

/// DIR/compare.csv: job, status and fitness in A and B and their difference, then each term's A, B and difference.
void WriteComparisonCsv(const std::string& path, const RunComparison& comparison);

}  // namespace orcs::batch
