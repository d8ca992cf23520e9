// What orcs-gap leaves in its output folder (docs/gap.md, "Output"): model.val (the fitted model as a value
// file), report.json (every figure), report.md (for people), traces/*.csv (for scripts/plot_gap.py).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/identify/gap_diagnosis.h"

namespace orcs::gap {

/// The report as JSON: rig, runs, gap before/refit/after (overall and per channel), every candidate's fit and
/// score, the verdict and the criterion.
nlohmann::json ReportJson(const identify::Diagnosis& diagnosis, const identify::Rig& rig, const identify::DiagnosisOptions& options);

/// The fitted model: the given model file's lines, then the fitted values.
std::string ModelValueFile(const identify::Diagnosis& diagnosis, const std::vector<ValueAssignment>& model);

/// The report in Markdown.
std::string ReportMarkdown(const identify::Diagnosis& diagnosis, const identify::Rig& rig, const identify::DiagnosisOptions& options);

/// Writes model.val, report.json, report.md and traces/<run>.<motor>.csv into `folder` (created). Throws
/// InputError when a file cannot be written.
void WriteReport(const std::string& folder, const identify::Diagnosis& diagnosis, const identify::Rig& rig,
                 const std::vector<ValueAssignment>& model, const identify::DiagnosisOptions& options);

/// Writes replays/ into `folder` for orcs-view (docs/gap.md, "Output"): per run, <run>.orcsrec (its replay under
/// the fitted model), <run>.given.orcsrec (under the model as given) and <run>.measured.orcsrec (the measured joint
/// angles, posed kinematically: MeasuredRecording). Recordings an earlier report left there are removed first.
/// Throws InputError when a file cannot be written.
void WriteReplays(const std::string& folder, const identify::Diagnosis& diagnosis, const identify::Rig& rig,
                  const std::vector<ValueAssignment>& model, const std::vector<identify::ReplayRun>& runs);

}  // namespace orcs::gap
