// orcs-batch regress as CI runs it: the real program with its embedded broker and local orcs-worker processes (and
// against a running orcs-broker) on 127.0.0.1. A model change — a motor parameter set with --set, outside every
// case's fingerprint — fails the shipped suite's cases with a JUnit report naming the cases and their numbers; a
// suite that no longer matches its baseline stops before anything runs; --update-baseline records a run that then
// passes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::BackgroundProcess;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::HasSubstr;

const std::string kBin = ORCS_BINARY_DIR "/bin/";
const std::string kShipped = ORCS_SOURCE_DIR "/scenarios/regress/";

nlohmann::json ReadJson(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

std::map<std::string, nlohmann::json> ResultsByCase(const std::string& path) {
  std::map<std::string, nlohmann::json> results;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const nlohmann::json result = nlohmann::json::parse(line);
    results[result["case"]] = result;
  }
  return results;
}

class OrcsBatchRegressTest : public ::testing::Test {
 protected:
  ProcessResult Regress(std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), {kBin + "orcs-batch", "regress"});
    return RunProcess(arguments);
  }
  // A copy of the shipped suite in the test's folder, its scenarios named by absolute path (so that its jobs, and
  // their fingerprints, are the shipped ones), with the shipped baseline beside it (NAME.baseline.json); only the
  // cases named in `keep` (all when empty), and only theirs in the baseline.
  std::string CopyOfShippedSuite(const std::string& name, const std::set<std::string>& keep = {},
                                 const std::function<void(nlohmann::json&)>& edit = nullptr) {
    nlohmann::json suite = ReadJson(kShipped + "suite.json");
    nlohmann::json baseline = ReadJson(kShipped + "suite.baseline.json");
    nlohmann::json cases = nlohmann::json::array();
    for (nlohmann::json& entry : suite["cases"]) {
      if (!keep.empty() && !keep.contains(entry["name"].get<std::string>())) {
        baseline["cases"].erase(entry["name"].get<std::string>());
        continue;
      }
      entry["scenario"] = (fs::path(kShipped) / entry["scenario"].get<std::string>()).lexically_normal().string();
      const nlohmann::json genome = entry.value("genome", nlohmann::json());
      if (genome.is_string() && genome.get<std::string>().starts_with("@")) {  // "@FILE", relative to the suite
        entry["genome"] = "@" + (fs::path(kShipped) / genome.get<std::string>().substr(1)).lexically_normal().string();
      }
      cases.push_back(entry);
    }
    suite["cases"] = cases;
    if (edit) edit(suite);
    dir_.Write(name + ".baseline.json", baseline.dump(2));
    return dir_.Write(name + ".json", suite.dump(2));
  }
  TempDir dir_;
};

TEST_F(OrcsBatchRegressTest, AMotorParameterChangedInTheModelFailsWithAReadableJUnitReport) {
  // The shipped suite's quicker cases, with their shipped baseline: what the fingerprints cover is unchanged.
  const std::string suite =
      CopyOfShippedSuite("suite", {"leg-swing", "sit-up", "pendulum-steps", "swing-oscillator", "pendulum-keyframes"});
  const std::string junit = dir_.PathOf("junit.xml");
  const ProcessResult result = Regress({suite, "--set", "/AngularMotor/FMaxFactor=0.8", "--junit", junit, "--workers",
                                        "2", "--out", dir_.PathOf("out")});
  std::cout << result.out;  // the table, in the CTest log
  ASSERT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_THAT(result.out, ::testing::ContainsRegex("pendulum-steps +[-0-9.e]+ +[-0-9.e]+ +[-0-9.e]+ +[0-9.e-]+ +FAIL"));

  const nlohmann::json baseline = ReadJson(dir_.PathOf("suite.baseline.json"));
  const std::map<std::string, nlohmann::json> results = ResultsByCase(dir_.PathOf("out/results.jsonl"));
  tinyxml2::XMLDocument report;
  ASSERT_EQ(report.LoadFile(junit.c_str()), tinyxml2::XML_SUCCESS);
  const tinyxml2::XMLElement* testsuite = report.FirstChildElement("testsuites")->FirstChildElement("testsuite");
  ASSERT_NE(testsuite, nullptr);
  EXPECT_GE(testsuite->IntAttribute("failures"), 1);
  int failures = 0;
  bool pendulum_failed = false;
  const std::regex numbers(
      "case '(\\S+)' regressed: fitness baseline (\\S+), measured (\\S+), difference (\\S+), tolerance (\\S+); "
      "terms moved: (.+)");
  for (const tinyxml2::XMLElement* testcase = testsuite->FirstChildElement("testcase"); testcase != nullptr;
       testcase = testcase->NextSiblingElement("testcase")) {
    const std::string name = testcase->Attribute("name");
    const tinyxml2::XMLElement* failure = testcase->FirstChildElement("failure");
    if (failure == nullptr) continue;
    ++failures;
    pendulum_failed |= name == "pendulum-steps";
    // The message names the case and its numbers: the baseline's, this run's, their difference, the tolerance.
    std::smatch match;
    const std::string message = failure->Attribute("message");
    ASSERT_TRUE(std::regex_match(message, match, numbers)) << message;
    EXPECT_EQ(match[1], name);
    EXPECT_STREQ(failure->Attribute("type"), "regression");
    const double recorded = std::stod(match[2]);
    const double measured = std::stod(match[3]);
    EXPECT_EQ(recorded, baseline["cases"][name]["fitness"].get<double>()) << name;
    EXPECT_EQ(measured, results.at(name)["fitness"].get<double>()) << name;
    EXPECT_EQ(std::stod(match[4]), measured - recorded) << name;
    EXPECT_GT(std::abs(measured - recorded), std::stod(match[5])) << name;
    // "terms moved: a 1 → 2, b 3 → 4": each a term of the case, with its baseline value.
    const std::string moved = match[6].str();
    const std::regex term("(\\w+) ([^ ,]+) → ([^ ,]+)");
    int terms = 0;
    for (auto it = std::sregex_iterator(moved.begin(), moved.end(), term); it != std::sregex_iterator();
         ++it, ++terms) {
      const nlohmann::json& recorded_terms = baseline["cases"][name]["terms"];
      ASSERT_TRUE(recorded_terms.contains((*it)[1].str())) << name << ": " << moved;
      EXPECT_EQ(std::stod((*it)[2]), recorded_terms[(*it)[1].str()].get<double>()) << name;
      EXPECT_EQ(std::stod((*it)[3]), results.at(name)["terms"][(*it)[1].str()].get<double>()) << name;
    }
    EXPECT_GE(terms, 1) << name << ": " << moved;
  }
  EXPECT_TRUE(pendulum_failed) << "the pendulum's motor holds the pole with less torque";
  EXPECT_EQ(failures, testsuite->IntAttribute("failures"));
  EXPECT_THAT(result.out, HasSubstr(std::to_string(failures) + " regressed, 0 failed jobs"));
}

TEST_F(OrcsBatchRegressTest, ASuiteThatNoLongerMatchesItsBaselineStopsBeforeAnythingRuns) {
  const std::string changed = CopyOfShippedSuite("changed", {}, [](nlohmann::json& suite) {
    suite["cases"][4]["values"] = {{"/AngularMotor/FMaxFactor", 0.8}};  // a case edited: another job
  });
  ProcessResult result = Regress({changed, "--out", dir_.PathOf("out")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("changed.baseline.json: field 'cases." +
                                    ReadJson(changed)["cases"][4]["name"].get<std::string>() + ".fingerprint'"));
  EXPECT_THAT(result.err, HasSubstr("run with --update-baseline if the change is intended"));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_FALSE(fs::exists(dir_.PathOf("out"))) << "nothing written, nothing submitted";

  result = Regress({CopyOfShippedSuite("renamed", {}, [](nlohmann::json& suite) { suite["name"] = "another"; }),
                    "--out", dir_.PathOf("out")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("field 'suite' expected \"another\""));

  result = Regress({dir_.Write("typo.json", R"({"cases": [{"name": "a", "scenaro": "x.json"}]})")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("typo.json: field 'cases[0].scenaro' expected no such field"));
  result = Regress({changed, "--baseline", dir_.PathOf("none.json")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("none.json: no baseline here; record one with --update-baseline"));
  EXPECT_FALSE(fs::exists(dir_.PathOf("out")));
}

TEST_F(OrcsBatchRegressTest, UpdateBaselineRecordsARunThatThenPassesOnARunningBroker) {
  dir_.Write("suite.json", R"({"name": "tiny", "cases": [
    {"name": "quarter", "scenario": ")" +
                               kShipped + R"(../examples/pendulum_keyframes.json"},
    {"name": "hips", "scenario": ")" +
                               kShipped + R"(../examples/swing_oscillator.json", "seed": 3,
     "genome": [20, 2, 0, 0, 20, 2, 3, 0], "tolerance": {"relative": 1e-12}}]})");
  const std::string suite = dir_.PathOf("suite.json");
  ProcessResult result = Regress({suite, "--update-baseline", "--workers", "1", "--out", dir_.PathOf("first")});
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_THAT(result.out, HasSubstr("2 cases: 2 recorded"));
  const nlohmann::json baseline = ReadJson(dir_.PathOf("suite.baseline.json"));
  EXPECT_EQ(baseline["suite"], "tiny");
  const std::map<std::string, nlohmann::json> first = ResultsByCase(dir_.PathOf("first/results.jsonl"));
  EXPECT_EQ(baseline["cases"]["hips"]["fitness"].dump(), first.at("hips")["fitness"].dump()) << "exact";
  EXPECT_EQ(baseline["cases"]["hips"]["terms"].dump(), first.at("hips")["terms"].dump());

  BackgroundProcess broker({kBin + "orcs-broker", "--client-port", "0", "--worker-port", "0", "--heartbeat", "0.1"});
  const std::optional<std::string> endpoints = broker.ReadLine(std::chrono::milliseconds(10000));
  ASSERT_TRUE(endpoints.has_value()) << broker.err();
  std::smatch match;
  ASSERT_TRUE(std::regex_match(*endpoints, match, std::regex("orcs-broker clients=(\\S+) workers=(\\S+)")));
  BackgroundProcess worker({kBin + "orcs-worker", "--connect", match[2], "--heartbeat", "0.1"});
  result = Regress({suite, "--broker", match[1], "--heartbeat", "0.1", "--junit", dir_.PathOf("j.xml"), "--out",
                    dir_.PathOf("second")});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_THAT(result.out, HasSubstr("2 cases: 2 pass"));
  EXPECT_THAT(dir_.Read("j.xml"), HasSubstr("failures=\"0\""));
}

}  // namespace
}  // namespace orcs
