// The JUnit report, parsed back with tinyxml2 as a CI system would read it.
#include "clients/regress/junit_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include "tests/support/temp_dir.h"

namespace orcs::regress {
namespace {

using ::testing::HasSubstr;

CaseComparison Passed() {
  CaseComparison comparison;
  comparison.name = "waist-bend";
  comparison.verdict = Verdict::kPass;
  comparison.status = "ok";
  comparison.baseline = comparison.now = 1.5;
  comparison.difference = 0.0;
  comparison.allowed = 1e-9;
  comparison.seconds = 1.25;
  return comparison;
}

CaseComparison Regressed() {
  CaseComparison comparison = Passed();
  comparison.name = "pendulum-steps";
  comparison.verdict = Verdict::kRegressed;
  comparison.now = 1.75;
  comparison.difference = 0.25;
  comparison.moved = {{"tracking_error", 12.5, 15.0}};
  return comparison;
}

CaseComparison JobFailed() {
  CaseComparison comparison = Passed();
  comparison.name = "stand-up";
  comparison.verdict = Verdict::kJobFailed;
  comparison.status = "invalid_input";
  comparison.message = "field 'x' expected <a number> & found \"y\"";
  return comparison;
}

const tinyxml2::XMLElement* Testcase(const tinyxml2::XMLElement* suite, const std::string& name) {
  for (const tinyxml2::XMLElement* testcase = suite->FirstChildElement("testcase"); testcase != nullptr;
       testcase = testcase->NextSiblingElement("testcase")) {
    if (testcase->Attribute("name", name.c_str())) return testcase;
  }
  return nullptr;
}

TEST(JUnitReportTest, OneTestcasePerCaseAndAFailureForEachThatDidNotPass) {
  const std::string xml = JUnitXml("orcs-shipped", {Passed(), Regressed(), JobFailed()}, 12.5);
  tinyxml2::XMLDocument document;
  ASSERT_EQ(document.Parse(xml.c_str()), tinyxml2::XML_SUCCESS) << xml;
  const tinyxml2::XMLElement* suites = document.FirstChildElement("testsuites");
  ASSERT_NE(suites, nullptr);
  EXPECT_EQ(suites->IntAttribute("tests"), 3);
  EXPECT_EQ(suites->IntAttribute("failures"), 2);
  const tinyxml2::XMLElement* suite = suites->FirstChildElement("testsuite");
  ASSERT_NE(suite, nullptr);
  EXPECT_STREQ(suite->Attribute("name"), "orcs-shipped");
  EXPECT_EQ(suite->IntAttribute("tests"), 3);
  EXPECT_EQ(suite->IntAttribute("failures"), 2);
  EXPECT_EQ(suite->IntAttribute("errors"), 0);
  EXPECT_DOUBLE_EQ(suite->DoubleAttribute("time"), 12.5);

  const tinyxml2::XMLElement* passed = Testcase(suite, "waist-bend");
  ASSERT_NE(passed, nullptr);
  EXPECT_STREQ(passed->Attribute("classname"), "orcs-shipped");
  EXPECT_DOUBLE_EQ(passed->DoubleAttribute("time"), 1.25);
  EXPECT_EQ(passed->FirstChildElement("failure"), nullptr);
  ASSERT_NE(passed->FirstChildElement("system-out"), nullptr);
  EXPECT_THAT(passed->FirstChildElement("system-out")->GetText(), HasSubstr("measured fitness: 1.5"));

  const tinyxml2::XMLElement* regression = Testcase(suite, "pendulum-steps");
  ASSERT_NE(regression, nullptr);
  const tinyxml2::XMLElement* failure = regression->FirstChildElement("failure");
  ASSERT_NE(failure, nullptr);
  EXPECT_STREQ(failure->Attribute("type"), "regression");
  EXPECT_STREQ(failure->Attribute("message"),
               "case 'pendulum-steps' regressed: fitness baseline 1.5, measured 1.75, difference 0.25, tolerance "
               "1e-09; terms moved: tracking_error 12.5 → 15");
  EXPECT_THAT(failure->GetText(), HasSubstr("term tracking_error: baseline 12.5, measured 15"));

  const tinyxml2::XMLElement* job_failed = Testcase(suite, "stand-up")->FirstChildElement("failure");
  ASSERT_NE(job_failed, nullptr);
  EXPECT_STREQ(job_failed->Attribute("type"), "job_failed");
  EXPECT_STREQ(job_failed->Attribute("message"),
               "case 'stand-up': the job did not run ok: invalid_input: field 'x' expected <a number> & found \"y\"; "
               "baseline fitness 1.5")
      << "special characters survive the XML";
}

TEST(JUnitReportTest, WritesTheFile) {
  test_support::TempDir dir;
  const std::string path = dir.PathOf("report.xml");
  WriteJUnit(path, "s", {Passed()}, 1.0);
  tinyxml2::XMLDocument document;
  ASSERT_EQ(document.LoadFile(path.c_str()), tinyxml2::XML_SUCCESS);
  EXPECT_EQ(document.FirstChildElement("testsuites")->IntAttribute("failures"), 0);
  EXPECT_THAT(dir.FileNames(), ::testing::ElementsAre("report.xml"));
}

}  // namespace
}  // namespace orcs::regress
