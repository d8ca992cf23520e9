#include "clients/regress/baseline.h"

#include <algorithm>
#include <filesystem>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::regress {
namespace {

constexpr const char* kIntended = "; run with --update-baseline if the change is intended";
constexpr const char* kComment =
    "Written by orcs-batch regress --update-baseline (docs/regress.md): the recorded fitness and terms of every "
    "case, and its job's fingerprint. Record it anew rather than editing it.";

BaselineCase ReadCase(const std::string& name, const JsonNode& node) {
  node.ExpectOnly({"fingerprint", "fitness", "terms"});
  BaselineCase entry;
  entry.name = name;
  entry.fingerprint = node.At("fingerprint").String("the job's fingerprint");
  entry.fitness = node.At("fitness").Number("a finite number");
  for (const auto& [term, value] : node.At("terms").Members())
    entry.terms.emplace_back(term, value.Number("a finite number"));
  return entry;
}

[[noreturn]] void Mismatch(const std::string& path, const std::string& what) {
  throw InputError(path, 0, what + kIntended);
}

}  // namespace

const BaselineCase* Baseline::Find(const std::string& name) const {
  for (const BaselineCase& entry : cases) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

Baseline ReadBaseline(const std::string& path) {
  if (!std::filesystem::exists(path)) {
    throw InputError(path, 0, "no baseline here; record one with --update-baseline (or name it with --baseline)");
  }
  const nlohmann::json document = ParseJson(ReadTextFile(path), path);
  const JsonNode root(document, "", path);
  root.ExpectOnly({"suite", "cases"});
  Baseline baseline;
  baseline.suite = root.At("suite").String("the suite's name");
  for (const auto& [name, entry] : root.At("cases").Members()) baseline.cases.push_back(ReadCase(name, entry));
  return baseline;
}

void WriteBaseline(const Baseline& baseline, const std::string& path) {
  nlohmann::ordered_json document;
  document["comment"] = kComment;
  document["suite"] = baseline.suite;
  nlohmann::ordered_json cases = nlohmann::ordered_json::object();
  for (const BaselineCase& entry : baseline.cases) {
    nlohmann::ordered_json terms = nlohmann::ordered_json::object();
    for (const auto& [term, value] : entry.terms) terms[term] = value;
    cases[entry.name] = {{"fingerprint", entry.fingerprint}, {"fitness", entry.fitness}, {"terms", terms}};
  }
  document["cases"] = std::move(cases);
  AtomicFile file(path);
  file.stream() << document.dump(2) << '\n';
  file.Commit();
}

void CheckBaselineMatches(const Baseline& baseline, const std::string& path, const Suite& suite,
                          const std::vector<std::string>& fingerprints) {
  if (baseline.suite != suite.name) {
    Mismatch(path, "field 'suite' expected \"" + suite.name + "\" (the name of " + suite.path + "), found \"" +
                       baseline.suite + "\": the baseline of another suite");
  }
  for (std::size_t i = 0; i < suite.cases.size(); ++i) {
    const SuiteCase& entry = suite.cases[i];
    const BaselineCase* recorded = baseline.Find(entry.name);
    if (recorded == nullptr) {
      Mismatch(path, "field 'cases' has no case " + text::Quote(entry.name) + " (" + suite.path + " " + entry.field + ")");
    }
    if (recorded->fingerprint != fingerprints.at(i)) {
      Mismatch(path, "field 'cases." + entry.name + ".fingerprint' expected " + fingerprints[i] + ", found " +
                         recorded->fingerprint + ": case '" + entry.name +
                         "' is not the job the baseline was recorded for (its scenario, a file it reads, its "
                         "genome, seed or values changed)");
    }
  }
  for (const BaselineCase& recorded : baseline.cases) {
    const bool in_suite = std::any_of(suite.cases.begin(), suite.cases.end(),
                                      [&](const SuiteCase& entry) { return entry.name == recorded.name; });
    if (!in_suite) Mismatch(path, "field 'cases." + recorded.name + "' is a case " + suite.path + " does not have");
  }
}

}  // namespace orcs::regress
