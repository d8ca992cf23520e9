#include "clients/regress/suite.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::regress {
namespace {

namespace fs = std::filesystem;

// Case names become job ids, JUnit test names and log file names: keep them to characters safe in all three.
bool IsSafeName(const std::string& name) {
  if (name.empty() || name.size() > 100 || name.front() == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
           c == '.';
  });
}

double NonNegative(const JsonNode& node) {
  const double value = node.Number("a number ≥ 0");
  if (value < 0.0) node.Fail("a number ≥ 0");
  return value;
}

// "tolerance": {"absolute": a, "relative": r}; a member left out keeps `fallback`'s.
Tolerance ReadTolerance(const JsonNode& node, const Tolerance& fallback) {
  node.ExpectOnly({"absolute", "relative"});
  Tolerance tolerance = fallback;
  if (node.Has("absolute")) tolerance.absolute = NonNegative(node.At("absolute"));
  if (node.Has("relative")) tolerance.relative = NonNegative(node.At("relative"));
  return tolerance;
}

// A file name in the suite, relative to the suite's folder.
std::string BesideSuite(const std::string& suite_path, const std::string& name) {
  return (fs::path(suite_path).parent_path() / name).lexically_normal().string();
}

runtime::Genome ReadGenome(const JsonNode& node, const std::string& suite_path) {
  if (node.value().is_string()) {
    const std::string text = node.value().get<std::string>();
    if (!text.starts_with("@") || text.size() == 1) node.Fail("a genome (an array, a network object or \"@FILE\")");
    return runtime::ParseGenomeOption("@" + BesideSuite(suite_path, text.substr(1)));
  }
  if (!node.value().is_array() && !node.value().is_object()) {
    node.Fail("a genome (an array, a network object or \"@FILE\")");
  }
  return runtime::Genome{node.value(), suite_path + " field " + text::Quote(node.path()), 0};
}

// "values": written as a scenario's "values" are, keyed by repository paths.
std::vector<std::pair<std::string, std::string>> ReadValues(const JsonNode& node) {
  std::vector<std::pair<std::string, std::string>> values;
  for (const auto& [path, value] : node.Members()) {
    if (!path.starts_with("/")) value.Fail("a repository path starting with '/' as the key", text::Quote(path));
  }
  for (const ValueAssignment& assignment : scene::ParseInlineValues(node)) {
    values.emplace_back(assignment.path, assignment.value);
  }
  return values;
}

// The scenario of a case; its errors keep the scenario's own file and field, prefixed by the case.
runtime::ScenarioInput ReadCaseScenario(const JsonNode& node, const std::string& suite_path, const std::string& name) {
  const std::string file = node.String("a scenario file name");
  try {
    return runtime::LoadScenario(BesideSuite(suite_path, file));
  } catch (const InputError& error) {
    throw InputError(suite_path, 0, "field " + text::Quote(node.path()) + " of case " + text::Quote(name) + ": " + error.what());
  }
}

// A case's "name", checked for the characters it may have (and the case for unknown keys).
std::string ReadCaseName(const JsonNode& node) {
  node.ExpectOnly({"name", "scenario", "genome", "seed", "values", "tolerance"});
  const JsonNode name = node.At("name");
  const std::string text = name.String("a case name");
  if (!IsSafeName(text)) name.Fail("a name of letters, digits, '-', '_' and '.' (not first), at most 100 characters");
  return text;
}

// Every case's name, before any case's files are read: a duplicate is one clear error, not a later one's.
void CheckNames(const std::vector<JsonNode>& elements) {
  std::map<std::string, std::string> seen;  // name → field of the case that has it first
  for (const JsonNode& element : elements) {
    const std::string name = ReadCaseName(element);
    const auto [it, inserted] = seen.emplace(name, element.path());
    if (!inserted)
      element.At("name").Fail("a name no other case has", "\"" + name + "\", the name of " + it->second + " too");
  }
}

SuiteCase ReadCase(const JsonNode& node, const Suite& suite) {
  SuiteCase entry;
  entry.field = node.path();
  entry.name = ReadCaseName(node);
  entry.scenario = ReadCaseScenario(node.At("scenario"), suite.path, entry.name);
  entry.genome = node.Has("genome") ? ReadGenome(node.At("genome"), suite.path) : runtime::DefaultGenome(entry.scenario);
  if (node.Has("seed")) entry.seed = node.At("seed").Unsigned("a seed (an integer ≥ 0)");
  if (node.Has("values")) entry.values = ReadValues(node.At("values"));
  entry.tolerance = node.Has("tolerance") ? ReadTolerance(node.At("tolerance"), suite.tolerance) : suite.tolerance;
  return entry;
}

}  // namespace

double Tolerance::Allowed(double baseline) const { return std::max(absolute, relative * std::abs(baseline)); }

Suite ReadSuite(const std::string& path) {
  const nlohmann::json document = ParseJson(ReadTextFile(path), path);
  const JsonNode root(document, "", path);
  root.ExpectOnly({"name", "tolerance", "cases"});
  Suite suite;
  suite.path = path;
  suite.name = root.Has("name") ? root.At("name").String("a suite name") : fs::path(path).stem().string();
  if (suite.name.empty()) root.At("name").Fail("a non-empty suite name");
  // The name is the default output folder runs/<name>: a label, never a path (the scenario's rule).
  const std::string problem = text::NameProblem(suite.name);
  if (!problem.empty()) {
    if (root.Has("name")) root.At("name").Fail(text::NameRule(), DescribeJson(root.At("name").value()) + " (" + problem + ")");
    throw InputError(path, 0, "the suite's name, its file name's stem " + text::Quote(suite.name) + ", is not " +
                                  text::NameRule() + " (" + problem + "): give it a \"name\"");
  }
  if (root.Has("tolerance")) suite.tolerance = ReadTolerance(root.At("tolerance"), Tolerance{});
  const JsonNode cases = root.At("cases");
  const std::vector<JsonNode> elements = cases.Elements();
  if (elements.empty()) cases.Fail("at least one case");
  CheckNames(elements);
  for (const JsonNode& element : elements) suite.cases.push_back(ReadCase(element, suite));
  return suite;
}

std::string DefaultBaselinePath(const std::string& suite_path, const std::string& engine) {
  fs::path path(suite_path);
  if (path.extension() == ".json") path.replace_extension();
  if (engine != "ODE") path += "." + text::ToLower(engine);
  path += ".baseline.json";
  return path.string();
}

}  // namespace orcs::regress
