// The baseline of a regression suite (docs/regress.md): per case the fitness and the fitness terms of a recorded
// run, exact (numbers round-trip), with what identifies the job they belong to — the suite's name, the case's
// name and its job's fingerprint — so that a baseline that does not describe the suite is refused, not compared.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "clients/regress/suite.h"

namespace orcs::regress {

/// One case as recorded.
struct BaselineCase {
  std::string name;                                   ///< the case's name in the suite
  std::string fingerprint;                            ///< JobFingerprint of the case's job when it was recorded
  double fitness = 0.0;                               ///< the job's fitness (aggregate over its parameter sets), exact
  std::vector<std::pair<std::string, double>> terms;  ///< each term's mean over the sets, unweighted, exact
};

/// A whole baseline file.
struct Baseline {
  std::string suite;                ///< the suite's name
  std::vector<BaselineCase> cases;  ///< in the suite's order when written
  /// The case named `name`, or nullptr.
  const BaselineCase* Find(const std::string& name) const;
};

/// Reads a baseline. Throws InputError naming the file and field for a missing file (with the hint to record
/// one with --update-baseline), malformed JSON, unknown keys or wrong types.
Baseline ReadBaseline(const std::string& path);

/// Writes the baseline (to a temporary name, renamed when complete). Throws InputError when it cannot.
void WriteBaseline(const Baseline& baseline, const std::string& path);

/// Checks that `baseline` (read from `path`) describes `suite`, whose cases' jobs have `fingerprints` (one per
/// case, in order): the same suite name, an entry for every case and for no other, the same fingerprint per case.
/// Throws InputError naming the baseline file and field, ending in "run with --update-baseline if the change is
/// intended".
void CheckBaselineMatches(const Baseline& baseline, const std::string& path, const Suite& suite,
                          const std::vector<std::string>& fingerprints);

}  // namespace orcs::regress
