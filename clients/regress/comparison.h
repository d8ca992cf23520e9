// One regression case's verdict (docs/regress.md): its result against its baseline — the fitness within the
// case's tolerance or not, the job failed, or no result at all — with the numbers and the terms that moved, as
// the table on stdout and the JUnit report show them.
#pragma once

#include <string>
#include <vector>

#include "clients/regress/baseline.h"
#include "clients/regress/suite.h"
#include "orcs/v1/result.pb.h"

namespace orcs::regress {

/// What became of a case.
enum class Verdict {
  kPass,       ///< ran ok, fitness within tolerance of the baseline
  kRegressed,  ///< ran ok, fitness beyond tolerance
  kJobFailed,  ///< the job ended with a status other than ok
  kNoResult,   ///< no result arrived (the batch was interrupted)
  kRecorded,   ///< --update-baseline: ran ok, recorded as the new baseline
};

/// A fitness term whose value is not the baseline's.
struct TermChange {
  std::string name;       ///< the term's name in the scenario
  double baseline = 0.0;  ///< recorded value (NaN when the baseline has no such term)
  double now = 0.0;       ///< this run's value (NaN when the result has no such term)
};

struct CaseComparison {
  std::string name;  ///< the case
  Verdict verdict = Verdict::kNoResult;
  double baseline = 0.0;          ///< recorded fitness (NaN with --update-baseline)
  double now = 0.0;               ///< this run's fitness (NaN unless the job ran ok)
  double difference = 0.0;        ///< now − baseline (NaN when either is missing)
  double allowed = 0.0;           ///< the tolerance around the baseline, ≥ 0 (NaN with --update-baseline)
  std::string status;             ///< the job's status as in results.jsonl ("ok", "timeout", ...; "" without a result)
  std::string message;            ///< the job's message when it did not run ok
  std::vector<TermChange> moved;  ///< terms whose value is not the baseline's bits, in the result's order
  double seconds = 0.0;           ///< wall-clock seconds the worker ran the job
  /// Whether the case counts as passed (kPass, or kRecorded).
  bool passed() const { return verdict == Verdict::kPass || verdict == Verdict::kRecorded; }
};

/// Compares `result` (nullptr when none arrived) with the case's `baseline`.
CaseComparison CompareCase(const SuiteCase& entry, const BaselineCase& baseline, const v1::Result* result);

/// The outcome of a case run to record a baseline: kRecorded when ok, else kJobFailed or kNoResult.
CaseComparison RecordCase(const SuiteCase& entry, const v1::Result* result);

/// The baseline entry a result gives (exact fitness and mean terms). The result must be ok.
BaselineCase BaselineOf(const std::string& name, const std::string& fingerprint, const v1::Result& result);

/// One line on what went wrong, for a JUnit <failure message>: for a regression the baseline, the measured
/// value, the difference and the tolerance, and the terms that moved; for a failed job its status and message.
/// Numbers in full (they read back to the same double). "" for a passed case.
std::string FailureMessage(const CaseComparison& comparison);

/// The readable table: case, baseline, now, difference, tolerance, PASS/FAIL, with a line per failure saying why.
std::string ComparisonTable(const std::vector<CaseComparison>& comparisons);

}  // namespace orcs::regress
