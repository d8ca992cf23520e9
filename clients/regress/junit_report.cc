#include "clients/regress/junit_report.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "model/core/atomic_file.h"
#include "model/core/text.h"

namespace orcs::regress {
namespace {

std::string Seconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", seconds);
  return text;
}

std::string Number(double value) { return std::isnan(value) ? "-" : text::FormatDouble(value); }

const char* FailureType(Verdict verdict) {
  switch (verdict) {
    case Verdict::kJobFailed:
      return "job_failed";
    case Verdict::kNoResult:
      return "no_result";
    default:
      return "regression";
  }
}

// The case's numbers, one per line: what a reader of the CI page wants next to the verdict.
std::string Details(const CaseComparison& comparison) {
  std::string text = "status: " + (comparison.status.empty() ? std::string("no result") : comparison.status) + "\n";
  text += "baseline fitness: " + Number(comparison.baseline) + "\n";
  text += "measured fitness: " + Number(comparison.now) + "\n";
  text += "difference: " + Number(comparison.difference) + "\n";
  text += "tolerance: " + Number(comparison.allowed) + "\n";
  if (!comparison.message.empty()) text += "message: " + comparison.message + "\n";
  for (const TermChange& term : comparison.moved) {
    text += "term " + term.name + ": baseline " + Number(term.baseline) + ", measured " + Number(term.now) + "\n";
  }
  return text;
}

void AddCase(tinyxml2::XMLElement& suite, const std::string& suite_name, const CaseComparison& comparison) {
  tinyxml2::XMLElement* testcase = suite.InsertNewChildElement("testcase");
  testcase->SetAttribute("name", comparison.name.c_str());
  testcase->SetAttribute("classname", suite_name.c_str());
  testcase->SetAttribute("time", Seconds(comparison.seconds).c_str());
  if (comparison.passed()) {
    testcase->InsertNewChildElement("system-out")->SetText(Details(comparison).c_str());
    return;
  }
  tinyxml2::XMLElement* failure = testcase->InsertNewChildElement("failure");
  failure->SetAttribute("message", FailureMessage(comparison).c_str());
  failure->SetAttribute("type", FailureType(comparison.verdict));
  failure->SetText(Details(comparison).c_str());
}

}  // namespace

std::string JUnitXml(const std::string& suite_name, const std::vector<CaseComparison>& comparisons, double seconds) {
  const auto failures = std::count_if(comparisons.begin(), comparisons.end(),
                                      [](const CaseComparison& comparison) { return !comparison.passed(); });
  tinyxml2::XMLDocument document;
  document.InsertEndChild(document.NewDeclaration());
  tinyxml2::XMLElement* suites = document.NewElement("testsuites");
  document.InsertEndChild(suites);
  suites->SetAttribute("name", "orcs-batch regress");
  tinyxml2::XMLElement* suite = suites->InsertNewChildElement("testsuite");
  suite->SetAttribute("name", suite_name.c_str());
  for (tinyxml2::XMLElement* element : {suites, suite}) {
    element->SetAttribute("tests", static_cast<int>(comparisons.size()));
    element->SetAttribute("failures", static_cast<int>(failures));
    element->SetAttribute("errors", 0);
    element->SetAttribute("time", Seconds(seconds).c_str());
  }
  for (const CaseComparison& comparison : comparisons) AddCase(*suite, suite_name, comparison);
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

void WriteJUnit(const std::string& path, const std::string& suite_name, const std::vector<CaseComparison>& comparisons,
                double seconds) {
  AtomicFile file(path);
  file.stream() << JUnitXml(suite_name, comparisons, seconds);
  file.Commit();
}

}  // namespace orcs::regress
