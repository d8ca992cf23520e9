// `orcs-batch regress` (docs/regress.md) before and after its batch: the plan — the suite read, one job per case,
// every input and the baseline checked before anything is submitted — and the report — each result compared with
// its baseline, the table on stdout, the JUnit file, or the baseline recorded anew. The batch itself runs through
// the session code every orcs-batch command shares (clients/runtime/batch_session.h).
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "clients/batch/batch_options.h"
#include "clients/regress/baseline.h"
#include "clients/regress/suite.h"
#include "clients/runtime/batch_input.h"
#include "clients/runtime/batch_session.h"

namespace orcs::regress {

/// Everything decided before the batch runs.
struct RegressPlan {
  Suite suite;                            ///< the suite, read, every case's scenario and genome loaded
  std::string baseline_path;              ///< --baseline, else DefaultBaselinePath(suite)
  Baseline baseline;                      ///< read and matched with the suite (empty with --update-baseline)
  bool update_baseline = false;           ///< --update-baseline: record the baseline from this run
  std::string junit_path;                 ///< --junit FILE.xml ("" = none)
  std::vector<std::string> fingerprints;  ///< per case, JobFingerprint of its job without --set's overrides
  std::vector<runtime::PlannedJob> jobs;    ///< per case, in suite order: job id = case name, --set's overrides last
};

/// Parses --set's "PATH=VALUE" (PATH starting with '/', VALUE not empty). Throws InputError "--set 'text': ...".
std::pair<std::string, std::string> ParseSetOption(const std::string& text);

/// Reads the suite, plans one job per case (the case's values, then every --set, as overrides), reads the baseline
/// and checks that it matches the suite (unless --update-baseline), then checks every job as a worker would.
/// Throws InputError naming the file and field. Writes to `notes` one line per case whose randomisation draws a
/// --set path anew in every parameter set (the set value does not reach that case, as a model change would not).
RegressPlan PlanRegression(const batch::BatchOptions& options, std::ostream& notes);

/// Compares each case's result with its baseline (or, with --update-baseline, writes the baseline when every case
/// ran ok), prints the table and a summary line to `out`, writes the JUnit file when asked. Returns the exit
/// code: 0 every case passed (or the baseline was written), 1 a regression, a failed job or a missing result.
int ReportRegression(const RegressPlan& plan, const runtime::BatchSummary& summary, const std::string& results_path,
                     std::ostream& out);

}  // namespace orcs::regress
