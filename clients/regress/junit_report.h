// The JUnit XML report of a regression run (docs/regress.md), the format CI systems (Jenkins, GitLab, GitHub
// actions' test reporters) display: one <testsuite> named after the suite, one <testcase> per case; a regression,
// a failed job or a missing result is a <failure> whose message says what moved and by how much.
#pragma once

#include <string>
#include <vector>

#include "clients/regress/comparison.h"

namespace orcs::regress {

/// The report as XML text: <testsuites><testsuite name tests failures errors="0" time><testcase name classname
/// time>, with <failure message type> ("regression", "job_failed" or "no_result") and the numbers in its text for
/// a case that did not pass, and the case's numbers in <system-out> for a case that passed. `seconds`: the batch's wall
/// clock time.
std::string JUnitXml(const std::string& suite_name, const std::vector<CaseComparison>& comparisons, double seconds);

/// Writes JUnitXml(...) to `path` (to a temporary name, renamed when complete). Throws InputError when it cannot.
void WriteJUnit(const std::string& path, const std::string& suite_name, const std::vector<CaseComparison>& comparisons,
                double seconds);

}  // namespace orcs::regress
