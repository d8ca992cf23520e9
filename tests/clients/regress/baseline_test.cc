// Baselines: written and read back to the same bits, and refused when they do not describe the suite.
#include "clients/regress/baseline.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::regress {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::EndsWith;
using ::testing::HasSubstr;

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

Suite TwoCases() {
  Suite suite;
  suite.path = "suite.json";
  suite.name = "two";
  suite.cases.resize(2);
  suite.cases[0].name = "first";
  suite.cases[0].field = "cases[0]";
  suite.cases[1].name = "second";
  suite.cases[1].field = "cases[1]";
  return suite;
}

Baseline Recorded() {
  Baseline baseline;
  baseline.suite = "two";
  baseline.cases.push_back({"first", "fnv1a64:0000000000000001", 0.1 + 0.2, {{"distance", -1.0 / 3.0}, {"falls", 0}}});
  baseline.cases.push_back({"second", "fnv1a64:0000000000000002", -1e-300, {{"energy", 12345.678901234567}}});
  return baseline;
}

const std::vector<std::string> kFingerprints = {"fnv1a64:0000000000000001", "fnv1a64:0000000000000002"};

class BaselineTest : public ::testing::Test {
 protected:
  std::string MatchError(const Baseline& baseline, const Suite& suite = TwoCases(),
                         const std::vector<std::string>& fingerprints = kFingerprints) {
    return InputErrorOf([&] { CheckBaselineMatches(baseline, "b.json", suite, fingerprints); });
  }
  TempDir dir_;
};

TEST_F(BaselineTest, WritesAndReadsBackTheSameBits) {
  const std::string path = dir_.PathOf("b.json");
  WriteBaseline(Recorded(), path);
  const Baseline read = ReadBaseline(path);
  EXPECT_EQ(read.suite, "two");
  ASSERT_EQ(read.cases.size(), 2u);
  for (const BaselineCase& expected : Recorded().cases) {
    const BaselineCase* found = read.Find(expected.name);
    ASSERT_NE(found, nullptr) << expected.name;
    EXPECT_EQ(found->fingerprint, expected.fingerprint);
    EXPECT_EQ(Bits(found->fitness), Bits(expected.fitness)) << expected.name;
    ASSERT_EQ(found->terms.size(), expected.terms.size());
    for (std::size_t i = 0; i < expected.terms.size(); ++i) {
      EXPECT_EQ(found->terms[i].first, expected.terms[i].first);
      EXPECT_EQ(Bits(found->terms[i].second), Bits(expected.terms[i].second));
    }
  }
  EXPECT_EQ(read.Find("third"), nullptr);
  EXPECT_NO_THROW(CheckBaselineMatches(read, path, TwoCases(), kFingerprints));
  EXPECT_THAT(dir_.FileNames(), ::testing::ElementsAre("b.json")) << "no temporary file left";
}

TEST_F(BaselineTest, AMissingOrMalformedBaselineIsAnErrorNamingTheFileAndField) {
  EXPECT_THAT(InputErrorOf([&] { ReadBaseline(dir_.PathOf("none.json")); }),
              HasSubstr("none.json: no baseline here; record one with --update-baseline"));
  const std::string bad_key = dir_.Write("k.json", R"({"suite": "two", "cases": {"a": {"fitnes": 1}}})");
  EXPECT_THAT(InputErrorOf([&] { ReadBaseline(bad_key); }),
              HasSubstr("k.json: field 'cases.a.fitnes' expected no such field"));
  const std::string bad_number =
      dir_.Write("n.json", R"({"suite": "two", "cases": {"a": {"fingerprint": "f", "fitness": "1", "terms": {}}}})");
  EXPECT_THAT(InputErrorOf([&] { ReadBaseline(bad_number); }),
              HasSubstr("n.json: field 'cases.a.fitness' expected a finite number, found the string \"1\""));
  const std::string no_suite = dir_.Write("s.json", R"({"cases": {}})");
  EXPECT_THAT(InputErrorOf([&] { ReadBaseline(no_suite); }), HasSubstr("s.json: field 'suite' expected a value"));
}

TEST_F(BaselineTest, ABaselineOfAnotherSuiteIsRefused) {
  Baseline other = Recorded();
  other.suite = "three";
  const std::string error = MatchError(other);
  EXPECT_THAT(error, HasSubstr("b.json: field 'suite' expected \"two\" (the name of suite.json), found \"three\""));
  EXPECT_THAT(error, EndsWith("run with --update-baseline if the change is intended"));
}

TEST_F(BaselineTest, AMissingCaseIsRefused) {
  Suite suite = TwoCases();
  suite.cases.push_back(suite.cases[0]);
  suite.cases[2].name = "third";
  suite.cases[2].field = "cases[2]";
  const std::string error = MatchError(Recorded(), suite, {kFingerprints[0], kFingerprints[1], "fnv1a64:3"});
  EXPECT_THAT(error, HasSubstr("b.json: field 'cases' has no case 'third' (suite.json cases[2])"));
  EXPECT_THAT(error, EndsWith("run with --update-baseline if the change is intended"));
}

TEST_F(BaselineTest, AnExtraCaseIsRefused) {
  Suite suite = TwoCases();
  suite.cases.pop_back();
  const std::string error = MatchError(Recorded(), suite, {kFingerprints[0]});
  EXPECT_THAT(error, HasSubstr("b.json: field 'cases.second' is a case suite.json does not have"));
  EXPECT_THAT(error, EndsWith("run with --update-baseline if the change is intended"));
}

TEST_F(BaselineTest, ACaseWhoseJobChangedIsRefused) {
  const std::string error = MatchError(Recorded(), TwoCases(), {kFingerprints[0], "fnv1a64:00000000000000ff"});
  EXPECT_THAT(error, HasSubstr("b.json: field 'cases.second.fingerprint' expected fnv1a64:00000000000000ff, found "
                               "fnv1a64:0000000000000002: case 'second' is not the job the baseline was recorded for"));
  EXPECT_THAT(error, EndsWith("run with --update-baseline if the change is intended"));
}

}  // namespace
}  // namespace orcs::regress
