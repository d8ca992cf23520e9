#include "model/core/value_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "model/core/error.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::HasSubstr;

// Each test works in its own fresh temporary directory, removed afterwards.
class ValueFileTest : public ::testing::Test {
 protected:
  TempDir dir_;
};

TEST_F(ValueFileTest, ReadSkipsCommentsAndBlankLinesAndTrims) {
  const std::string file = dir_.Write("a.val",
                                      "# a comment\n"
                                      "\n"
                                      "  /a/b = 3  \n"
                                      "   \t\n"
                                      "  # indented comment with = sign\n"
                                      "/c=  two words \r\n"
                                      "/d=\n"
                                      "/e=x=y\n");
  const std::vector<ValueAssignment> assignments = ValueFile::Read(file);
  ASSERT_EQ(assignments.size(), 4u);
  EXPECT_EQ(assignments[0].path, "/a/b");
  EXPECT_EQ(assignments[0].value, "3");
  EXPECT_EQ(assignments[0].file, file);
  EXPECT_EQ(assignments[0].line, 3);
  EXPECT_EQ(assignments[1].path, "/c");
  EXPECT_EQ(assignments[1].value, "two words");
  EXPECT_EQ(assignments[1].line, 6);
  EXPECT_EQ(assignments[2].path, "/d");
  EXPECT_EQ(assignments[2].value, "");
  EXPECT_EQ(assignments[3].path, "/e");
  EXPECT_EQ(assignments[3].value, "x=y");  // only the first '=' separates
  EXPECT_EQ(assignments[3].line, 8);
}

TEST_F(ValueFileTest, ApplySetsValuesInOrderIncludingBooleans) {
  VariableRepository repository;
  repository.Add("/a/b", 0);
  repository.Add("/On", false);
  repository.Add("/Off", true);
  repository.Add("/Gain", 0.0);
  repository.Add("/Position", Eigen::Vector3d::Zero().eval());
  const std::string file = dir_.Write("a.val",
                                      "  /a/b = 3  \n"
                                      "/On=T\n"
                                      "/Off=F\n"
                                      "/Gain=1\n"
                                      "/Gain=0.25\n"  // later lines win
                                      "/Position=(1, 2, 3)\n");
  ValueFile::Apply(file, repository);
  EXPECT_EQ(repository.Get("/a/b").as_int(), 3);
  EXPECT_TRUE(repository.Get("/On").as_bool());
  EXPECT_FALSE(repository.Get("/Off").as_bool());
  EXPECT_EQ(repository.Get("/Gain").as_double(), 0.25);
  EXPECT_EQ(repository.Get("/Position").as_vector3(), Eigen::Vector3d(1, 2, 3));
}

TEST_F(ValueFileTest, IncludeIsRelativeToTheIncludingFile) {
  dir_.Write("sub/inner.val", "/b=2\n#include deeper/deepest.val\n/c=3\n");
  dir_.Write("sub/deeper/deepest.val", "/d=4\n");
  // A decoy next to main.val that must not be picked for the include inside sub/inner.val.
  dir_.Write("deeper/deepest.val", "/d=999\n");
  const std::string main = dir_.Write("main.val", "/a=1\n#include <sub/inner.val>\n/e=5\n");
  const std::vector<ValueAssignment> assignments = ValueFile::Read(main);
  ASSERT_EQ(assignments.size(), 5u);
  const std::vector<std::string> paths{assignments[0].path, assignments[1].path, assignments[2].path,
                                       assignments[3].path, assignments[4].path};
  EXPECT_EQ(paths, (std::vector<std::string>{"/a", "/b", "/d", "/c", "/e"}));
  EXPECT_EQ(assignments[2].value, "4");
  EXPECT_EQ(fs::path(assignments[1].file), dir_.path() / "sub" / "inner.val");
  EXPECT_EQ(assignments[1].line, 1);
  EXPECT_EQ(fs::path(assignments[2].file), dir_.path() / "sub" / "deeper" / "deepest.val");
  EXPECT_EQ(assignments[4].file, main);
  EXPECT_EQ(assignments[4].line, 3);
}

TEST_F(ValueFileTest, IncludeWorksFromAFileNamedWithoutADirectory) {
  dir_.Write("inner.val", "/b=2\n");
  dir_.Write("main.val", "#include inner.val\n");
  const fs::path previous = fs::current_path();
  fs::current_path(dir_.path());
  std::vector<ValueAssignment> assignments;
  EXPECT_NO_THROW(assignments = ValueFile::Read("main.val"));
  fs::current_path(previous);
  ASSERT_EQ(assignments.size(), 1u);
  EXPECT_EQ(assignments[0].path, "/b");
}

TEST_F(ValueFileTest, IncludeCycleThrowsMentioningIncludeDepth) {
  dir_.Write("a.val", "/a=1\n#include b.val\n");
  dir_.Write("b.val", "#include a.val\n");
  const std::string message = InputErrorOf([&] { ValueFile::Read(dir_.PathOf("a.val")); });
  EXPECT_THAT(message, HasSubstr("#include nested deeper than"));
  EXPECT_THAT(message, HasSubstr(std::to_string(ValueFile::kMaxIncludeDepth)));

  const std::string self = dir_.Write("self.val", "#include self.val\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(self); }), HasSubstr("nested deeper"));
}

TEST_F(ValueFileTest, IncludesUpToTheMaximumDepthAreFine) {
  // main.val includes f1.val, which includes f2.val, ..., kMaxIncludeDepth files deep.
  const int depth = ValueFile::kMaxIncludeDepth;
  for (int i = 1; i <= depth; ++i) {
    dir_.Write("f" + std::to_string(i) + ".val",
               i < depth ? "#include f" + std::to_string(i + 1) + ".val\n" : std::string("/x=1\n"));
  }
  const std::string main = dir_.Write("main.val", "#include f1.val\n");
  EXPECT_EQ(ValueFile::Read(main).size(), 1u);
  // One more level is too deep.
  dir_.Write("f" + std::to_string(depth) + ".val", "#include f" + std::to_string(depth + 1) + ".val\n");
  dir_.Write("f" + std::to_string(depth + 1) + ".val", "/x=1\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(main); }), HasSubstr("nested deeper"));
}

TEST_F(ValueFileTest, MissingIncludeNamesFileAndLine) {
  const std::string main = dir_.Write("main.val", "/a=1\n\n#include missing.val\n");
  const std::string message = InputErrorOf([&] { ValueFile::Read(main); });
  EXPECT_THAT(message, HasSubstr(main + ":3:"));
  EXPECT_THAT(message, HasSubstr("missing.val"));
}

TEST_F(ValueFileTest, IncludeWithoutAFileNameIsAnError) {
  const std::string main = dir_.Write("main.val", "#include\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(main); }), HasSubstr(main + ":1:"));
  const std::string brackets = dir_.Write("brackets.val", "/a=1\n#include <>\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(brackets); }), HasSubstr(brackets + ":2:"));
}

TEST_F(ValueFileTest, LineWithoutEqualsThrowsWithFileAndLine) {
  const std::string file = dir_.Write("a.val", "# header\n/a=1\n/b 2\n");
  try {
    ValueFile::Read(file);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(file + ":3:"));
    EXPECT_THAT(error.what(), HasSubstr("/b 2"));
    EXPECT_EQ(error.source(), file);
    EXPECT_EQ(error.line(), 3);
  }
}

TEST_F(ValueFileTest, EmptyPathThrowsWithFileAndLine) {
  const std::string file = dir_.Write("a.val", "=3\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(file); }), HasSubstr(file + ":1:"));
}

TEST_F(ValueFileTest, ErrorInAnIncludedFileNamesThatFile) {
  const std::string inner = dir_.Write("sub/inner.val", "/a=1\nnonsense\n");
  const std::string main = dir_.Write("main.val", "#include sub/inner.val\n");
  const std::string message = InputErrorOf([&] { ValueFile::Read(main); });
  EXPECT_THAT(message, HasSubstr("inner.val:2:"));
}

TEST_F(ValueFileTest, UnknownPathThrowsWithFileAndLineAndChangesNothing) {
  VariableRepository repository;
  Value& gain = repository.Add("/Gain", 1.0);
  int calls = 0;
  gain.AddObserver([&calls](const Value&) { ++calls; });
  const std::string file = dir_.Write("a.val", "/Gain=2\n/Nowhere=3\n");
  const std::string message = InputErrorOf([&] { ValueFile::Apply(file, repository); });
  EXPECT_THAT(message, HasSubstr(file + ":2:"));
  EXPECT_THAT(message, HasSubstr("/Nowhere"));
  EXPECT_EQ(gain.as_double(), 1.0);  // the valid first line was not applied either
  EXPECT_EQ(calls, 0);
}

TEST_F(ValueFileTest, UnknownLongPathIsNamedInFull) {
  VariableRepository repository;
  repository.Add("/Simulation/ODE/ContactMaxCorrectingVelocity", 1.0);
  const std::string file = dir_.Write("a.val", "/Simulation/ODE/ContactMaxCorrectingVelocityy=2\n");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Apply(file, repository); }),
              HasSubstr("'/Simulation/ODE/ContactMaxCorrectingVelocityy'"));
}

TEST_F(ValueFileTest, BadValueTextThrowsWithFileAndLineAndChangesNothing) {
  VariableRepository repository;
  repository.Add("/Gain", 1.0);
  repository.Add("/Flag", false);
  const std::string file = dir_.Write("a.val", "/Gain=2\n# comment\n/Flag=yes\n");
  const std::string message = InputErrorOf([&] { ValueFile::Apply(file, repository); });
  EXPECT_THAT(message, HasSubstr(file + ":3:"));
  EXPECT_THAT(message, HasSubstr("/Flag"));
  EXPECT_THAT(message, HasSubstr("T or F"));
  EXPECT_THAT(message, HasSubstr("'yes'"));
  EXPECT_EQ(repository.Get("/Gain").as_double(), 1.0);
  EXPECT_FALSE(repository.Get("/Flag").as_bool());
}

TEST_F(ValueFileTest, UnreadableFileIsNamed) {
  const std::string missing = dir_.PathOf("does_not_exist.val");
  const std::string message = InputErrorOf([&] { ValueFile::Read(missing); });
  EXPECT_THAT(message, HasSubstr(missing));
  VariableRepository repository;
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Apply(missing, repository); }), HasSubstr(missing));
  // A directory is not a value file either.
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Read(dir_.path().string()); }), HasSubstr(dir_.path().string()));
}

TEST_F(ValueFileTest, SaveWritesHeadersAndRoundTrips) {
  VariableRepository saved;
  saved.Add("/Flag", true);
  saved.Add("/Count", -42);
  saved.Add("/Tenth", 0.1);
  saved.Add("/Third", 1.0 / 3.0);
  saved.Add("/Tiny", 1e-300);
  saved.Add("/Name", "two words");
  saved.Add("/Colour", Color{1, 2, 3, 4});
  saved.Add("/Position", Eigen::Vector3d(0.1, 1.0 / 3.0, -2e-7));
  saved.Add("/Orientation", Eigen::Quaterniond(0.5, 1.0 / 3.0, -0.25, 0.7));
  const std::string file = dir_.PathOf("saved.val");
  ValueFile::Save(file, saved, "2024-01-02 03:04:05");

  const std::string contents = dir_.Read(file);
  EXPECT_TRUE(contents.starts_with("#ORCS Values\n#Saved at: 2024-01-02 03:04:05\n")) << contents;
  EXPECT_THAT(contents, HasSubstr("/Flag=T\n"));
  EXPECT_THAT(contents, HasSubstr("/Tenth=0.1\n"));

  VariableRepository loaded;
  loaded.Add("/Flag", false);
  loaded.Add("/Count", 0);
  loaded.Add("/Tenth", 0.0);
  loaded.Add("/Third", 0.0);
  loaded.Add("/Tiny", 0.0);
  loaded.Add("/Name", "");
  loaded.Add("/Colour", Color{});
  loaded.Add("/Position", Eigen::Vector3d::Zero().eval());
  loaded.Add("/Orientation", Eigen::Quaterniond::Identity());
  ValueFile::Apply(file, loaded);
  EXPECT_TRUE(loaded.Get("/Flag").as_bool());
  EXPECT_EQ(loaded.Get("/Count").as_int(), -42);
  EXPECT_EQ(loaded.Get("/Tenth").as_double(), 0.1);
  EXPECT_EQ(loaded.Get("/Third").as_double(), 1.0 / 3.0);
  EXPECT_EQ(loaded.Get("/Tiny").as_double(), 1e-300);
  EXPECT_EQ(loaded.Get("/Name").as_string(), "two words");
  EXPECT_EQ(loaded.Get("/Colour").as_color(), (Color{1, 2, 3, 4}));
  EXPECT_EQ(loaded.Get("/Position").as_vector3(), Eigen::Vector3d(0.1, 1.0 / 3.0, -2e-7));
  EXPECT_EQ(loaded.Get("/Orientation").as_quaternion().coeffs(),
            Eigen::Quaterniond(0.5, 1.0 / 3.0, -0.25, 0.7).coeffs());
  for (int id = 0; id < saved.size(); ++id) {
    EXPECT_EQ(loaded.Get(saved.path(id)).ToString(), saved.value(id).ToString()) << saved.path(id);
  }
}

TEST_F(ValueFileTest, SaveWritesOnlyMatchingPathsInRegistrationOrder) {
  VariableRepository repository;
  repository.Add("/Sim/B/Mass", 2.0);
  repository.Add("/PID/Gain", 3.0);
  repository.Add("/Sim/A/Mass", 1.0);
  const std::string file = dir_.PathOf("masses.val");
  ValueFile::Save(file, repository, "now", "/Sim/.*");
  EXPECT_EQ(dir_.Read(file), "#ORCS Values\n#Saved at: now\n/Sim/B/Mass=2\n/Sim/A/Mass=1\n");
}

TEST_F(ValueFileTest, SaveLeavesNoTemporaryFiles) {
  VariableRepository repository;
  repository.Add("/A", 1);
  const std::string file = dir_.PathOf("out.val");
  ValueFile::Save(file, repository, "now");
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"out.val"});
}

TEST_F(ValueFileTest, SaveWithInvalidRegexThrowsAndWritesNothing) {
  VariableRepository repository;
  repository.Add("/A", 1);
  EXPECT_THROW(ValueFile::Save(dir_.PathOf("out.val"), repository, "now", "(("), InputError);
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(ValueFileTest, SaveToAnUnwritablePlaceNamesTheFile) {
  VariableRepository repository;
  repository.Add("/A", 1);
  const std::string file = dir_.PathOf("no_such_folder/out.val");
  EXPECT_THAT(InputErrorOf([&] { ValueFile::Save(file, repository, "now"); }), HasSubstr(file));
  EXPECT_FALSE(fs::exists(file));
}


// A string value with a line feed was saved as extra lines, which loading applied as assignments of their own
// (issue 47, item 4: "PVC\n/Simulation/TimeStepSize=0.1"). Save refuses it, naming the path, and writes nothing.
TEST_F(ValueFileTest, SaveRefusesAValueWithAControlCharacterAndWritesNothing) {
  for (const std::string& bad : {std::string("PVC\n/Simulation/TimeStepSize=0.1"), std::string("PVC\r/A=2"),
                                  std::string("PVC\0x", 5), std::string("a\x1b[2Jb"), std::string("a\x7f")}) {
    VariableRepository repository;
    repository.Add("/Simulation/TimeStepSize", 0.01);
    repository.Add("/Sim/Floor/Material", bad);
    const std::string file = dir_.PathOf("floor.val");
    const std::string error = InputErrorOf([&] { ValueFile::Save(file, repository, "now"); });
    EXPECT_THAT(error, HasSubstr("/Sim/Floor/Material: the value holds control character U+00")) << error;
    EXPECT_EQ(std::count(error.begin(), error.end(), '\n'), 0) << "one line";
    EXPECT_TRUE(fs::is_empty(dir_.path())) << "nothing saved, no temporary left";
  }
  VariableRepository tab;
  tab.Add("/Name", "a\tb");
  ValueFile::Save(dir_.PathOf("tab.val"), tab, "now");
  EXPECT_EQ(dir_.Read("tab.val"), "#ORCS Values\n#Saved at: now\n/Name=a\tb\n") << "a tab is one line's text";
}

// Loading refuses what a value file cannot represent — a NUL, a stray CR, an escape — naming the line and the
// character, and sets nothing; a CR ending a line (CRLF) and tabs are text.
TEST_F(ValueFileTest, ReadRefusesControlCharactersNamingTheLine) {
  VariableRepository repository;
  repository.Add("/A", 1);
  repository.Add("/Name", "x");
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {{std::string("/A=2\n/Name=P\0VC\n", 16), ":2: control character U+0000 (NUL) at column 8"},
               {"/A=2\r/Name=y\n", ":1: control character U+000D (carriage return) at column 5"},
               {"# note\n/Name=\x1b[31m\n", ":2: control character U+001B (escape) at column 7"}};
  for (const auto& c : cases) {
    const std::string file = dir_.Write("bad.val", c.text);
    const std::string error = InputErrorOf([&] { ValueFile::Apply(file, repository); });
    EXPECT_THAT(error, HasSubstr(file + c.expected)) << error;
    EXPECT_EQ(std::count(error.begin(), error.end(), '\n'), 0) << "one line";
    EXPECT_EQ(repository.Get("/A").as_int(), 1) << "nothing set";
  }
  const std::string crlf = dir_.Write("crlf.val", "/A=3\r\n/Name=\ta b\r\n");
  ValueFile::Apply(crlf, repository);
  EXPECT_EQ(repository.Get("/A").as_int(), 3);
  EXPECT_EQ(repository.Get("/Name").as_string(), "a b");
}

}  // namespace
}  // namespace orcs
