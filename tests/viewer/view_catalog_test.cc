// What orcs-view makes of folders, in particular of runs still in progress: a folder known only by its
// progress.json, recordings that appear after the server started, and the dashboard's job → replay links.
#include "viewer/view_catalog.h"

#include <gtest/gtest.h>

#include <fstream>

#include "model/core/error.h"
#include "model/evaluation/recorder.h"
#include "model/scene/world_setup.h"
#include "tests/support/temp_dir.h"

namespace orcs::viewer {
namespace {

class ViewCatalogTest : public ::testing::Test {
 protected:
  /// A progress.json as clients/runtime/progress_file.h writes it.
  void WriteProgress(const std::string& folder, const std::string& command, const std::string& state,
                     const std::string& broker_batch = "") {
    nlohmann::json progress = {{"format", "orcs-progress"}, {"version", 1}, {"command", command}, {"state", state}};
    if (!broker_batch.empty()) progress["broker_batch"] = broker_batch;
    dir_.Write(folder + "/progress.json", progress.dump());
  }
  /// Listing needs only the file's name: its contents are read when the page opens it.
  void WriteRecording(const std::string& relative) { dir_.Write(relative, "not read by these tests"); }

  std::vector<std::string> Kinds(const ViewCatalog& catalog) const {
    std::vector<std::string> kinds;
    for (const ViewItem& item : catalog.Items()) kinds.push_back(item.kind + ":" + item.label);
    return kinds;
  }

  test_support::TempDir dir_;
};

TEST_F(ViewCatalogTest, AnEvolveRunThatHasJustStartedIsKnownByItsProgress) {
  WriteProgress("run", "evolve", "running");
  ViewCatalog catalog({dir_.PathOf("run")});
  ASSERT_EQ(Kinds(catalog), std::vector<std::string>{"evolve:run"});
  nlohmann::json evolve = *catalog.EvolveJson("e0");
  EXPECT_EQ(evolve["progress"]["state"], "running");
  EXPECT_TRUE(evolve["generations"].empty());
  EXPECT_TRUE(evolve["recording"].is_null());

  // Two generations and the winner later: the same item shows them, without a restart.
  dir_.Write("run/fitness.csv", "generation,best,median\n0,1.5,0.5\n1,2.5,1.0\n");
  dir_.Write("run/best/results.jsonl", "{\"id\":\"winner\",\"status\":\"OK\",\"fitness\":2.5}\n");
  WriteRecording("run/best/recordings/winner.orcsrec");
  WriteProgress("run", "evolve", "finished");
  evolve = *catalog.EvolveJson("e0");
  EXPECT_EQ(evolve["generations"].size(), 2u);
  EXPECT_EQ(evolve["progress"]["state"], "finished");
  ASSERT_TRUE(evolve["recording"].is_string());
  const ViewItem* winner = catalog.Find(evolve["recording"].get<std::string>());
  ASSERT_NE(winner, nullptr);
  EXPECT_EQ(winner->label, "winner");
  EXPECT_EQ(Kinds(catalog), (std::vector<std::string>{"evolve:run", "batch:run / winner and validation",
                                                      "recording:winner"}));
  catalog.EvolveJson("e0");  // looking again adds nothing twice
  EXPECT_EQ(catalog.Items().size(), 3u);
}

TEST_F(ViewCatalogTest, ABatchInProgressListsRecordingsAsTheyAppear) {
  WriteProgress("sweep", "sweep", "running");
  ViewCatalog catalog({dir_.PathOf("sweep")});
  ASSERT_EQ(Kinds(catalog), std::vector<std::string>{"batch:sweep"});
  nlohmann::json batch = *catalog.BatchJson("b0");
  EXPECT_TRUE(batch["jobs"].empty());
  EXPECT_EQ(batch["progress"]["command"], "sweep");

  dir_.Write("sweep/results.jsonl.partial", "{\"id\":\"job-1\",\"status\":\"OK\",\"fitness\":1}\n");
  WriteRecording("sweep/recordings/job-1.orcsrec");
  batch = *catalog.BatchJson("b0");
  ASSERT_EQ(batch["jobs"].size(), 1u);
  EXPECT_TRUE(batch["jobs"][0]["recording"].is_string()) << batch.dump();
}

// orcs-robot --view: a folder whose recording grows while the robot moves is one item, its recordings read again as
// they grow (up to the last complete frame), without a restart.
TEST_F(ViewCatalogTest, ARobotRunIsFollowedAsItsRecordingGrows) {
  dir_.Write("bend/robot_run.json", R"({"played": "waist_bend.csv", "joints": ["Waist"], "agent": "Humanoid"})");
  WriteProgress("bend", "robot", "running");
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(0);
  evaluation::Recorder recorder(simulation, evaluation::RecordingSource{});
  const auto steps = [&](int n) {
    for (int i = 0; i < n; ++i) {
      simulation.Step();
      recorder.Sample();
    }
  };
  steps(5);
  std::ofstream file(dir_.PathOf("bend/robot.orcsrec"), std::ios::binary);
  const auto append = [&](const std::string& bytes) {
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.flush();
  };
  append(recorder.TakeFlushed());
  ViewCatalog catalog({dir_.PathOf("bend")});
  ASSERT_EQ(Kinds(catalog), (std::vector<std::string>{"robot:bend", "recording:robot"}));
  const nlohmann::json robot = *catalog.RobotJson("p0");
  EXPECT_EQ(robot["robot"], "r0");
  EXPECT_EQ(robot["twin"], nullptr) << "no twin.orcsrec yet";
  EXPECT_EQ(robot["run"]["played"], "waist_bend.csv");
  EXPECT_EQ(robot["progress"]["state"], "running");
  EXPECT_EQ(catalog.Recording("r0")->frame_count(), 6);
  EXPECT_FALSE(catalog.Recording("r0")->finished);
  steps(7);
  append(recorder.TakeFlushed());
  EXPECT_EQ(catalog.Recording("r0")->frame_count(), 13) << "read again: the file grew";
  EXPECT_GT((*catalog.RobotJson("p0"))["bytes"]["robot"].get<std::uint64_t>(), robot["bytes"]["robot"].get<std::uint64_t>());
  steps(2);
  append(recorder.Finish());
  EXPECT_EQ(catalog.Recording("r0")->frame_count(), 15);
  EXPECT_TRUE(catalog.Recording("r0")->finished);
  EXPECT_FALSE(catalog.GapJson("p0").has_value()) << "an id of another kind";
}

TEST_F(ViewCatalogTest, AGapDiagnosisUnderWayHasNoReportYet) {
  WriteProgress("gap", "gap", "running");
  ViewCatalog catalog({dir_.PathOf("gap")});
  const nlohmann::json gap = *catalog.GapJson("g0");
  EXPECT_TRUE(gap["missing_effect"].is_null());
  EXPECT_TRUE(gap["runs"].empty());
  EXPECT_EQ(gap["progress"]["state"], "running");
}

TEST_F(ViewCatalogTest, AProgressFileOfAnotherProgramDoesNotMakeAFolderViewable) {
  dir_.Write("other/progress.json", R"({"command": "evolve", "state": "running"})");
  try {
    ViewCatalog catalog({dir_.PathOf("other")});
    FAIL() << "accepted a folder with a foreign progress.json only";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("nothing viewable"), std::string::npos) << error.what();
  }
  dir_.Write("broken/results.jsonl", "");
  dir_.Write("broken/progress.json", "{ not json");
  ViewCatalog catalog({dir_.PathOf("broken")});
  EXPECT_TRUE((*catalog.BatchJson("b0"))["progress"].is_null());
}

TEST_F(ViewCatalogTest, ReplaysLinkTheBrokersBatchAndJobToTheRecording) {
  WriteProgress("a", "run", "running", "c0ffee");
  dir_.Write("a/results.jsonl.partial", "");
  WriteRecording("a/recordings/job-2.orcsrec");
  WriteProgress("local", "run", "finished");  // no broker batch named: no links
  WriteRecording("local/recordings/job-2.orcsrec");
  ViewCatalog catalog({dir_.PathOf("a"), dir_.PathOf("local")});
  nlohmann::json replays = catalog.ReplaysJson();
  ASSERT_EQ(replays.size(), 1u) << replays.dump();
  EXPECT_EQ(replays[0]["batch"], "c0ffee");
  EXPECT_EQ(replays[0]["job"], "job-2");
  const ViewItem* recording = catalog.Find(replays[0]["recording"].get<std::string>());
  ASSERT_NE(recording, nullptr);
  EXPECT_EQ(recording->path, dir_.PathOf("a/recordings/job-2.orcsrec"));

  WriteRecording("a/recordings/job-7.orcsrec");  // recorded since
  replays = catalog.ReplaysJson();
  ASSERT_EQ(replays.size(), 2u);
  EXPECT_EQ(replays[1]["job"], "job-7");
}

}  // namespace
}  // namespace orcs::viewer
