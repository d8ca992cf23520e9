#include "model/core/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/core/error.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("orcs_atomic_file_test_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    ASSERT_TRUE(fs::create_directories(dir_));
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  std::vector<std::string> FileNames() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    return names;
  }

  static std::string ReadAll(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream buffer;
    buffer << in.rdbuf();
    return buffer.str();
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, CommitMakesTheFileAppearWithItsContents) {
  const fs::path path = dir_ / "out.txt";
  AtomicFile file(path.string());
  file.stream() << "hello\n";
  EXPECT_FALSE(fs::exists(path));  // only a temporary file so far
  EXPECT_EQ(FileNames().size(), 1u);
  file.Commit();
  EXPECT_EQ(ReadAll(path), "hello\n");
  EXPECT_EQ(FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, DestroyedWithoutCommitLeavesNoFileAndNoTemporaryFile) {
  const fs::path path = dir_ / "out.txt";
  {
    AtomicFile file(path.string());
    file.stream() << "half written";
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFileTest, ExceptionBeforeCommitLeavesNoFile) {
  const fs::path path = dir_ / "out.txt";
  try {
    AtomicFile file(path.string());
    file.stream() << "half written";
    throw std::runtime_error("failure while writing");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtomicFileTest, AbandonedRewriteKeepsThePreviousFile) {
  const fs::path path = dir_ / "out.txt";
  std::ofstream(path) << "previous\n";
  {
    AtomicFile file(path.string());
    file.stream() << "new but unfinished";
  }
  EXPECT_EQ(ReadAll(path), "previous\n");
  EXPECT_EQ(FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, CommitReplacesThePreviousFile) {
  const fs::path path = dir_ / "out.txt";
  std::ofstream(path) << "previous, longer text\n";
  AtomicFile file(path.string());
  file.stream() << "new\n";
  file.Commit();
  EXPECT_EQ(ReadAll(path), "new\n");
  EXPECT_EQ(FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, UncreatableFileThrowsNamingIt) {
  const std::string path = (dir_ / "missing_folder" / "out.txt").string();
  try {
    AtomicFile file(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path));
  }
}

}  // namespace
}  // namespace orcs
