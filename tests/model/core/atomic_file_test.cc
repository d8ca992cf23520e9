#include "model/core/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/core/error.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;
using ::testing::HasSubstr;

class AtomicFileTest : public ::testing::Test {
 protected:
  TempDir dir_;
};

TEST_F(AtomicFileTest, CommitMakesTheFileAppearWithItsContents) {
  const fs::path path = dir_.path() / "out.txt";
  AtomicFile file(path.string());
  file.stream() << "hello\n";
  EXPECT_FALSE(fs::exists(path));  // only a temporary file so far
  EXPECT_EQ(dir_.FileNames().size(), 1u);
  file.Commit();
  EXPECT_EQ(dir_.Read(path), "hello\n");
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, DestroyedWithoutCommitLeavesNoFileAndNoTemporaryFile) {
  const fs::path path = dir_.path() / "out.txt";
  {
    AtomicFile file(path.string());
    file.stream() << "half written";
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(AtomicFileTest, ExceptionBeforeCommitLeavesNoFile) {
  const fs::path path = dir_.path() / "out.txt";
  try {
    AtomicFile file(path.string());
    file.stream() << "half written";
    throw std::runtime_error("failure while writing");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(AtomicFileTest, AbandonedRewriteKeepsThePreviousFile) {
  const fs::path path = dir_.path() / "out.txt";
  std::ofstream(path) << "previous\n";
  {
    AtomicFile file(path.string());
    file.stream() << "new but unfinished";
  }
  EXPECT_EQ(dir_.Read(path), "previous\n");
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, CommitReplacesThePreviousFile) {
  const fs::path path = dir_.path() / "out.txt";
  std::ofstream(path) << "previous, longer text\n";
  AtomicFile file(path.string());
  file.stream() << "new\n";
  file.Commit();
  EXPECT_EQ(dir_.Read(path), "new\n");
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, UncreatableFileThrowsNamingIt) {
  const std::string path = dir_.PathOf("missing_folder/out.txt");
  try {
    AtomicFile file(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path));
  }
}

}  // namespace
}  // namespace orcs
