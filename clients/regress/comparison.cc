#include "clients/regress/comparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "model/core/text.h"
#include "proto/result_json.h"

namespace orcs::regress {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Each term's mean over the sets, in the scenario's order: the "terms" of results.jsonl.
std::vector<std::pair<std::string, double>> MeanTerms(const v1::Result& result) {
  std::vector<std::pair<std::string, double>> terms;
  const nlohmann::ordered_json json = proto::ResultToJson(result);
  for (auto it = json["terms"].begin(); it != json["terms"].end(); ++it) {
    terms.emplace_back(it.key(), it.value().get<double>());
  }
  return terms;
}

// Terms whose bits differ, or that only one side has.
std::vector<TermChange> MovedTerms(const std::vector<std::pair<std::string, double>>& baseline,
                                   const std::vector<std::pair<std::string, double>>& now) {
  std::vector<TermChange> moved;
  auto value_in = [](const std::vector<std::pair<std::string, double>>& terms, const std::string& name) {
    for (const auto& [term, value] : terms) {
      if (term == name) return value;
    }
    return kNaN;
  };
  for (const auto& [name, value] : now) {
    const double recorded = value_in(baseline, name);
    if (!(recorded == value)) moved.push_back({name, recorded, value});
  }
  for (const auto& [name, value] : baseline) {
    if (std::isnan(value_in(now, name))) moved.push_back({name, value, kNaN});
  }
  return moved;
}

// What every comparison starts with: the result's status, message, time and fitness.
CaseComparison FromResult(const SuiteCase& entry, const v1::Result* result) {
  CaseComparison comparison;
  comparison.name = entry.name;
  comparison.baseline = comparison.difference = comparison.allowed = comparison.now = kNaN;
  if (result == nullptr) {
    comparison.verdict = Verdict::kNoResult;
    comparison.message = "no result: the batch was interrupted";
    return comparison;
  }
  comparison.status = std::string(proto::StatusName(result->status()));
  comparison.seconds = result->timings().run_seconds();
  if (result->status() != v1::Result::OK) {
    comparison.verdict = Verdict::kJobFailed;
    comparison.message = result->message();
    return comparison;
  }
  comparison.now = result->fitness();
  return comparison;
}

std::string Number(double value) { return std::isnan(value) ? "-" : text::FormatDouble(value); }

// A number for the table: 10 significant digits, "-" when there is none.
std::string Short(double value, const char* format = "%.10g") {
  if (std::isnan(value)) return "-";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// "; baseline fitness B" for a case that has no fitness to compare, so the message still says what was expected.
std::string BaselineNote(const CaseComparison& comparison) {
  return std::isnan(comparison.baseline) ? "" : "; baseline fitness " + Number(comparison.baseline);
}

std::string VerdictName(const CaseComparison& comparison) {
  switch (comparison.verdict) {
    case Verdict::kPass:
      return "PASS";
    case Verdict::kRecorded:
      return "RECORDED";
    case Verdict::kRegressed:
      return "FAIL";
    case Verdict::kJobFailed:
      return "FAIL (" + comparison.status + ")";
    case Verdict::kNoResult:
      return "FAIL (no result)";
  }
  return "FAIL";
}

std::string Padded(const std::string& text, std::size_t width) {
  return text + std::string(width > text.size() ? width - text.size() : 0, ' ') + "  ";
}

}  // namespace

CaseComparison CompareCase(const SuiteCase& entry, const BaselineCase& baseline, const v1::Result* result) {
  CaseComparison comparison = FromResult(entry, result);
  comparison.baseline = baseline.fitness;
  comparison.allowed = entry.tolerance.Allowed(baseline.fitness);
  if (result == nullptr || result->status() != v1::Result::OK) return comparison;
  comparison.difference = comparison.now - comparison.baseline;
  comparison.moved = MovedTerms(baseline.terms, MeanTerms(*result));
  comparison.verdict = std::abs(comparison.difference) <= comparison.allowed ? Verdict::kPass : Verdict::kRegressed;
  return comparison;
}

CaseComparison RecordCase(const SuiteCase& entry, const v1::Result* result) {
  CaseComparison comparison = FromResult(entry, result);
  if (result != nullptr && result->status() == v1::Result::OK) comparison.verdict = Verdict::kRecorded;
  return comparison;
}

BaselineCase BaselineOf(const std::string& name, const std::string& fingerprint, const v1::Result& result) {
  return BaselineCase{name, fingerprint, result.fitness(), MeanTerms(result)};
}

std::string FailureMessage(const CaseComparison& comparison) {
  switch (comparison.verdict) {
    case Verdict::kPass:
    case Verdict::kRecorded:
      return "";
    case Verdict::kNoResult:
      return "case " + text::Quote(comparison.name) + ": " + comparison.message + BaselineNote(comparison);
    case Verdict::kJobFailed:
      return "case " + text::Quote(comparison.name) + ": the job did not run ok: " + comparison.status +
             (comparison.message.empty() ? "" : ": " + comparison.message) + BaselineNote(comparison);
    case Verdict::kRegressed:
      break;
  }
  std::string message = "case " + text::Quote(comparison.name) + " regressed: fitness baseline " + Number(comparison.baseline) +
                        ", measured " + Number(comparison.now) + ", difference " + Number(comparison.difference) +
                        ", tolerance " + Number(comparison.allowed);
  if (comparison.moved.empty()) return message + "; no term moved";
  message += "; terms moved:";
  for (std::size_t i = 0; i < comparison.moved.size(); ++i) {
    const TermChange& term = comparison.moved[i];
    message += std::string(i == 0 ? " " : ", ") + term.name + " " + Number(term.baseline) + " → " + Number(term.now);
  }
  return message;
}

std::string ComparisonTable(const std::vector<CaseComparison>& comparisons) {
  std::size_t width = 4;
  for (const CaseComparison& comparison : comparisons) width = std::max(width, comparison.name.size());
  constexpr std::size_t kNumber = 17;
  std::string table = Padded("case", width) + Padded("baseline", kNumber) + Padded("now", kNumber) +
                      Padded("difference", 10) + Padded("tolerance", 9) + "result\n";
  for (const CaseComparison& comparison : comparisons) {
    table += Padded(comparison.name, width) + Padded(Short(comparison.baseline), kNumber) +
             Padded(Short(comparison.now), kNumber) + Padded(Short(comparison.difference, "%.3g"), 10) +
             Padded(Short(comparison.allowed, "%.3g"), 9) + VerdictName(comparison) + "\n";
  }
  for (const CaseComparison& comparison : comparisons) {
    if (!comparison.passed()) table += "  " + FailureMessage(comparison) + "\n";
  }
  return table;
}

}  // namespace orcs::regress
