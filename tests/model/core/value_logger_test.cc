#include "model/core/value_logger.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "model/core/error.h"
#include "model/core/text.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

class ValueLoggerTest : public ::testing::Test {
 protected:
  static std::vector<std::string> Lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  // The numbers of a CSV row, each parsed exactly; fails the test on a field that is not a number.
  static std::vector<double> Numbers(const std::string& row) {
    std::vector<double> numbers;
    for (std::string_view field : text::Split(row, ',')) {
      const auto number = text::ParseDouble(field);
      EXPECT_TRUE(number.has_value()) << "field '" << field << "' of '" << row << "'";
      numbers.push_back(number.value_or(-12345.0));
    }
    return numbers;
  }

  TempDir dir_;
};

TEST_F(ValueLoggerTest, ColumnNamesSpreadVectorsQuaternionsAndColours) {
  VariableRepository repository;
  repository.Add("/Sim/Box/Position", Eigen::Vector3d::Zero().eval());
  repository.Add("/Sim/Box/Orientation", Eigen::Quaterniond::Identity());
  repository.Add("/Sim/Box/Colour", Color{});
  repository.Add("/Sim/Box/Mass", 1.0);
  repository.Add("/Sim/Box/Touching", false);
  repository.Add("/Sim/Box/Contacts", 0);
  repository.Add("/Other", 0.0);
  const ValueLogger logger(repository, {"/Sim/Box/.*"});
  EXPECT_THAT(logger.column_names(),
              ElementsAre("time", "/Sim/Box/Position.x", "/Sim/Box/Position.y", "/Sim/Box/Position.z",
                          "/Sim/Box/Orientation.w", "/Sim/Box/Orientation.x", "/Sim/Box/Orientation.y",
                          "/Sim/Box/Orientation.z", "/Sim/Box/Colour.r", "/Sim/Box/Colour.g",
                          "/Sim/Box/Colour.b", "/Sim/Box/Colour.a", "/Sim/Box/Mass", "/Sim/Box/Touching",
                          "/Sim/Box/Contacts"));
}

TEST_F(ValueLoggerTest, ColumnsFollowRepositoryOrderAndDuplicatesAreLoggedOnce) {
  VariableRepository repository;
  repository.Add("/A", 1.0);
  repository.Add("/B", 2.0);
  repository.Add("/C", 3.0);
  const ValueLogger logger(repository, {"/C", "/A", ".*", "/(A|C)"});
  EXPECT_THAT(logger.column_names(), ElementsAre("time", "/A", "/B", "/C"));
}

TEST_F(ValueLoggerTest, RegexMatchingNothingThrowsNamingIt) {
  VariableRepository repository;
  repository.Add("/A", 1.0);
  try {
    ValueLogger logger(repository, {"/A", "/Sim/.*/Nothing"});
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("/Sim/.*/Nothing"));
  }
  EXPECT_THROW(ValueLogger(repository, {"/A("}), InputError);
  // Long expressions are named in full.
  const std::string long_regex = "/Sim/Humanoid/Right/Knee/(DesiredAngle|JointAngle)";
  try {
    ValueLogger logger(repository, {long_regex});
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("'" + long_regex + "'"));
  }
}

TEST_F(ValueLoggerTest, FileAppearsOnlyAtFinish) {
  VariableRepository repository;
  repository.Add("/A", 1.0);
  ValueLogger logger(repository, {"/A"});
  const fs::path path = dir_.path() / "trace.csv";
  logger.Open(path.string(), {});
  logger.Sample(0.0);
  logger.Sample(0.01);
  EXPECT_FALSE(fs::exists(path));
  logger.Finish();
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"trace.csv"});  // no temporary file left behind
}

TEST_F(ValueLoggerTest, AbandonedLogLeavesNoFile) {
  VariableRepository repository;
  repository.Add("/A", 1.0);
  {
    ValueLogger logger(repository, {"/A"});
    logger.Open(dir_.PathOf("trace.csv"), {"comment"});
    logger.Sample(0.0);
  }
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(ValueLoggerTest, HeaderAndRowsParseBackExactly) {
  VariableRepository repository;
  Value& mass = repository.Add("/Sim/Box/Mass", 0.1);
  Value& position = repository.Add("/Sim/Box/Position", Eigen::Vector3d(1.0 / 3.0, -0.0, 1e-300));
  Value& orientation = repository.Add("/Sim/Box/Orientation", Eigen::Quaterniond(0.5, 0.1, 0.2, 0.3));
  Value& touching = repository.Add("/Sim/Box/Touching", true);
  Value& count = repository.Add("/Sim/Box/Contacts", 7);
  ValueLogger logger(repository, {"/Sim/Box/.*"});
  const fs::path path = dir_.path() / "trace.csv";
  logger.Open(path.string(), {"program: orcs-test", "seed: 42"});
  logger.Sample(0.0);
  mass.Set(2.0 / 3.0);
  position.Set(Eigen::Vector3d(-1e10, 0.7, 123.456));
  orientation.Set(Eigen::Quaterniond(1, 0, 0, 0));
  touching.Set(false);
  count.Set(-3);
  logger.Sample(0.01);
  logger.Finish();

  const std::vector<std::string> lines = Lines(path);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], "# program: orcs-test");
  EXPECT_EQ(lines[1], "# seed: 42");
  EXPECT_EQ(lines[2],
            "# columns: time,/Sim/Box/Mass,/Sim/Box/Position.x,/Sim/Box/Position.y,/Sim/Box/Position.z,"
            "/Sim/Box/Orientation.w,/Sim/Box/Orientation.x,/Sim/Box/Orientation.y,/Sim/Box/Orientation.z,"
            "/Sim/Box/Touching,/Sim/Box/Contacts");
  const std::vector<double> first = Numbers(lines[3]);
  const std::vector<double> first_expected{0.0, 0.1, 1.0 / 3.0, -0.0, 1e-300, 0.5, 0.1, 0.2, 0.3, 1.0, 7.0};
  ASSERT_EQ(first.size(), first_expected.size());
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i], first_expected[i]) << "column " << i;
  EXPECT_TRUE(std::signbit(first[3]));  // -0.0 keeps its sign

  const std::vector<double> second = Numbers(lines[4]);
  const std::vector<double> second_expected{0.01, 2.0 / 3.0, -1e10, 0.7, 123.456, 1.0, 0.0, 0.0, 0.0, 0.0, -3.0};
  ASSERT_EQ(second.size(), second_expected.size());
  for (size_t i = 0; i < second.size(); ++i) EXPECT_EQ(second[i], second_expected[i]) << "column " << i;
  // Booleans are 0/1, integers plain.
  EXPECT_TRUE(lines[3].ends_with(",1,7"));
  EXPECT_TRUE(lines[4].ends_with(",0,-3"));
}

// An in-memory log stops at its bound: whole rows up to it, then one comment line saying when and why, then nothing
// however long the run goes on.
TEST_F(ValueLoggerTest, AnInMemoryLogEndsWithOneLineAtItsBound) {
  VariableRepository repository;
  repository.Add("/Sim/Box/Mass", 0.25);
  ValueLogger logger(repository, {"/Sim/Box/Mass"});
  logger.OpenInMemory({"bounded"});
  logger.Sample(0.0);
  const std::string unbounded = logger.TakeText();
  const std::size_t header = unbounded.size() - std::string("0,0.25\n").size();

  constexpr std::size_t kRow = 10;  // "0.01,0.25\n" ... "0.09,0.25\n": 10 bytes each
  logger.OpenInMemory({"bounded"}, header + 3 * kRow + 5);
  for (int i = 1; i <= 1000; ++i) logger.Sample(i / 100.0);
  EXPECT_TRUE(logger.truncated());
  const std::string text = logger.TakeText();
  std::vector<std::string> lines;
  for (std::string_view line : text::Split(text, '\n')) lines.emplace_back(line);
  ASSERT_EQ(lines.size(), 7u) << text;  // 2 header lines, 3 rows, the truncation line, "" after the last newline
  EXPECT_EQ(lines[2], "0.01,0.25");
  EXPECT_EQ(lines[4], "0.03,0.25");
  EXPECT_THAT(lines[5], AllOf(HasSubstr("# log truncated at time 0.04 s"),
                              HasSubstr("it reached its bound of " + std::to_string(header + 3 * kRow + 5) + " bytes")));
  EXPECT_EQ(lines[6], "");

  // Opened again, the same logger starts afresh.
  logger.OpenInMemory({"bounded"});
  logger.Sample(0.0);
  EXPECT_FALSE(logger.truncated());
  EXPECT_EQ(logger.TakeText(), unbounded);
}

TEST_F(ValueLoggerTest, ColourAndStringColumns) {
  VariableRepository repository;
  repository.Add("/Colour", Color{10, 20, 30, 40});
  repository.Add("/Plain", "walk");
  repository.Add("/Tricky", "a,\"b\"");
  ValueLogger logger(repository, {".*"});
  const fs::path path = dir_.path() / "trace.csv";
  logger.Open(path.string(), {});
  logger.Sample(1.5);
  logger.Finish();
  const std::vector<std::string> lines = Lines(path);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "# columns: time,/Colour.r,/Colour.g,/Colour.b,/Colour.a,/Plain,/Tricky");
  EXPECT_EQ(lines[1], "1.5,10,20,30,40,walk,\"a,\"\"b\"\"\"");
}

TEST_F(ValueLoggerTest, ReopeningTheSamePathStartsAFreshFile) {
  VariableRepository repository;
  Value& a = repository.Add("/A", 1.0);
  ValueLogger logger(repository, {"/A"});
  const fs::path path = dir_.path() / "trace.csv";
  logger.Open(path.string(), {"first"});
  logger.Sample(0.0);
  logger.Open(path.string(), {"second"});  // e.g. after a reset: the first attempt is abandoned
  a.Set(2.0);
  logger.Sample(0.5);
  logger.Finish();
  EXPECT_THAT(Lines(path), ElementsAre("# second", "# columns: time,/A", "0.5,2"));
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"trace.csv"});
}

TEST_F(ValueLoggerTest, OpenInAMissingFolderThrowsNamingThePath) {
  VariableRepository repository;
  repository.Add("/A", 1.0);
  ValueLogger logger(repository, {"/A"});
  const std::string path = dir_.PathOf("missing/trace.csv");
  try {
    logger.Open(path, {});
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path));
  }
}

}  // namespace
}  // namespace orcs
