// progress.json: what it holds, when it is rewritten, and how a command's end shows in it.
#include "clients/runtime/progress_file.h"

#include <gtest/gtest.h>

#include <sstream>

#include "clients/runtime/progress_display.h"
#include "tests/support/temp_dir.h"

namespace orcs::runtime {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using Clock = ProgressFile::Clock;

class ProgressFileTest : public ::testing::Test {
 protected:
  nlohmann::json Written() const { return nlohmann::json::parse(dir_.Read(kProgressFile)); }
  test_support::TempDir dir_;
};

TEST_F(ProgressFileTest, IsWrittenAtOnceAsRunning) {
  ProgressFile file(dir_.path().string(), "evolve", Clock::time_point{});
  const nlohmann::json written = Written();
  EXPECT_EQ(written["format"], "orcs-progress");
  EXPECT_EQ(written["version"], 1);
  EXPECT_EQ(written["command"], "evolve");
  EXPECT_EQ(written["state"], "running");
  EXPECT_TRUE(written["updated_unix"].is_number());
  file.Finish("finished");
}

TEST_F(ProgressFileTest, IsRewrittenAtMostOnceASecondUnlessForced) {
  const Clock::time_point start{};
  ProgressFile file(dir_.path().string(), "run", start);
  file.Set("done", 1);
  file.Update(start + milliseconds(500));
  EXPECT_FALSE(Written().contains("done")) << "rewritten within the second";
  file.Update(start + seconds(1));
  EXPECT_EQ(Written()["done"], 1);
  file.Set("done", 2);
  file.Update(start + milliseconds(1200), true);
  EXPECT_EQ(Written()["done"], 2);
  file.Set("done", nullptr);  // null removes the field
  file.Finish("finished");
  EXPECT_FALSE(Written().contains("done"));
}

TEST_F(ProgressFileTest, TheEndIsRecordedAndAnExceptionLeavesFailed) {
  {
    ProgressFile file(dir_.path().string(), "run");
    file.Finish("interrupted");
  }
  EXPECT_EQ(Written()["state"], "interrupted");
  {
    ProgressFile file(dir_.path().string(), "run");  // destroyed without Finish: the command threw
  }
  EXPECT_EQ(Written()["state"], "failed");
  EXPECT_EQ(dir_.FileNames(), std::vector<std::string>{kProgressFile}) << "a temporary file was left";
}

TEST_F(ProgressFileTest, WithoutAFolderNothingIsWritten) {
  ProgressFile file("", "run");
  file.Set("done", 3);
  file.Finish("finished");
  EXPECT_EQ(file.fields()["done"], 3);
  EXPECT_TRUE(dir_.FileNames().empty());
}

TEST_F(ProgressFileTest, AFolderThatVanishedIsSaidOnceAndTheRunGoesOn) {
  const std::string folder = (dir_.path() / "gone").string();
  std::filesystem::create_directory(folder);
  ProgressFile file(folder, "run");
  std::filesystem::remove_all(folder);
  testing::internal::CaptureStderr();
  file.Update(Clock::now() + seconds(5), true);
  file.Finish("finished");
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("progress.json"), std::string::npos) << said;
  EXPECT_EQ(said.find('\n'), said.size() - 1) << "said more than once: " << said;
}

TEST_F(ProgressFileTest, TheDisplayKeepsTheFileUpToDate) {
  const Clock::time_point start{};
  std::ostringstream out;
  ProgressFile file(dir_.path().string(), "sweep", start);
  ProgressDisplay display(out, 40, false, start);
  display.SetLabel("generation 3/10: ");
  display.WriteTo(&file);
  display.Update(9, 1, start + seconds(5));
  nlohmann::json written = Written();
  EXPECT_EQ(written["label"], "generation 3/10");
  EXPECT_EQ(written["done"], 10);
  EXPECT_EQ(written["ok"], 9);
  EXPECT_EQ(written["failed"], 1);
  EXPECT_EQ(written["total"], 40);
  EXPECT_DOUBLE_EQ(written["jobs_per_second"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(written["eta_seconds"].get<double>(), 15.0);
  display.Update(10, 1, start + milliseconds(5500));  // within the second: the file keeps 10
  EXPECT_EQ(Written()["done"], 10);
  display.Finish(40, 0, start + seconds(6));  // the last count is always written
  written = Written();
  EXPECT_EQ(written["done"], 40);
  EXPECT_FALSE(written.contains("eta_seconds")) << "nothing is left to wait for";
  file.Finish("finished");
}

}  // namespace
}  // namespace orcs::runtime
