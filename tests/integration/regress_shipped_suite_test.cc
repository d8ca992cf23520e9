// The project's own CI run of the shipped regression suite (scenarios/regress/suite.json): the real orcs-batch
// regress with its embedded broker and two local orcs-worker processes on 127.0.0.1 must pass against the stored
// baseline, and its JUnit report must say so case by case. Registered as the CTest test regress_shipped_suite.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using test_support::ProcessResult;
using test_support::RunProcess;
using ::testing::HasSubstr;

// Each engine keeps its own baseline beside the suite: suite.baseline.json (ODE) and suite.mujoco.baseline.json.
class RegressShippedSuite : public ::testing::TestWithParam<std::string> {};

TEST_P(RegressShippedSuite, PassesAgainstItsBaseline) {
  test_support::TempDir dir;
  const std::string suite = ORCS_SOURCE_DIR "/scenarios/regress/suite.json";
  const std::string junit = dir.PathOf("junit.xml");
  const ProcessResult result =
      RunProcess({ORCS_BINARY_DIR "/bin/orcs-batch", "regress", suite, "--engine", GetParam(), "--junit", junit,
                  "--workers", "2", "--out", dir.PathOf("out")});
  std::cout << result.out;  // the table, in the CTest log
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;

  const nlohmann::json suite_json = nlohmann::json::parse(std::ifstream(suite));
  const std::size_t cases = suite_json["cases"].size();
  EXPECT_THAT(result.out, HasSubstr(std::to_string(cases) + " cases: " + std::to_string(cases) + " pass"));
  tinyxml2::XMLDocument report;
  ASSERT_EQ(report.LoadFile(junit.c_str()), tinyxml2::XML_SUCCESS);
  const tinyxml2::XMLElement* testsuite = report.FirstChildElement("testsuites")->FirstChildElement("testsuite");
  ASSERT_NE(testsuite, nullptr);
  EXPECT_EQ(testsuite->IntAttribute("tests"), static_cast<int>(cases));
  EXPECT_EQ(testsuite->IntAttribute("failures"), 0);
  std::set<std::string> names;
  for (const tinyxml2::XMLElement* testcase = testsuite->FirstChildElement("testcase"); testcase != nullptr;
       testcase = testcase->NextSiblingElement("testcase")) {
    names.insert(testcase->Attribute("name"));
    EXPECT_EQ(testcase->FirstChildElement("failure"), nullptr) << testcase->Attribute("name");
  }
  std::set<std::string> expected;
  for (const nlohmann::json& entry : suite_json["cases"]) expected.insert(entry["name"].get<std::string>());
  EXPECT_EQ(names, expected);
}

INSTANTIATE_TEST_SUITE_P(Engines, RegressShippedSuite, ::testing::Values("ODE", "MuJoCo"),
                         [](const ::testing::TestParamInfo<std::string>& engine) { return engine.param; });

}  // namespace
}  // namespace orcs
