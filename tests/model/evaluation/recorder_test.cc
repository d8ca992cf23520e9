#include "model/evaluation/recorder.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <map>

#include "model/evaluation/recording_reader.h"
#include "model/scene/environment_reader.h"
#include "model/scene/world_setup.h"
#include "tests/support/temp_dir.h"

namespace orcs::evaluation {
namespace {

constexpr int kSteps = 150;

// Every numeric value of the repository as bits, so that two runs can be compared exactly.
std::vector<std::string> RepositoryBits(const VariableRepository& repository) {
  std::vector<std::string> bits;
  for (int id = 0; id < repository.size(); ++id) bits.push_back(repository.value(id).ToString());
  return bits;
}

// The standing A-Series with a motor commanded away from zero, so that something moves.
void SetUpStanding(scene::Simulation& simulation) {
  scene::SetUpWorld(simulation, "", {}, {});
  simulation.Reset(7);
  simulation.repository().Set("/Sim/Humanoid/Right/Knee/DesiredAngle", "40");
}

TEST(RecorderTest, RecordingDoesNotChangeTheRun) {
  scene::Simulation plain;
  scene::Simulation recorded;
  SetUpStanding(plain);
  SetUpStanding(recorded);
  Recorder recorder(recorded, RecordingSource{});
  for (int i = 0; i < kSteps; ++i) {
    plain.Step();
    recorded.Step();
    recorder.Sample();
  }
  EXPECT_EQ(RepositoryBits(plain.repository()), RepositoryBits(recorded.repository()));
  EXPECT_EQ(recorder.frame_count(), kSteps + 1);
}

TEST(RecorderTest, ReaderGetsBackEveryFrameAndChannel) {
  scene::Simulation simulation;
  SetUpStanding(simulation);
  Recorder recorder(simulation, RecordingSource{"recorder_test", "(default)", "", 7, 0, nullptr});
  for (int i = 0; i < kSteps; ++i) {
    simulation.Step();
    recorder.Sample();
  }
  const Recording recording = ParseRecording(recorder.Finish(), "test.orcsrec");
  ASSERT_EQ(recording.frame_count(), kSteps + 1);
  EXPECT_EQ(recording.times.front(), 0.0);
  EXPECT_EQ(recording.times.back(), simulation.time());
  EXPECT_EQ(recording.header["source"]["seed"], 7);
  EXPECT_EQ(recording.header["program"], "recorder_test");

  // The last frame holds the repository's values now, as float32.
  const VariableRepository& repository = simulation.repository();
  const int knee = recording.FindChannel("/Sim/Humanoid/Right/Knee/JointAngle");
  ASSERT_GE(knee, 0);
  EXPECT_EQ(recording.value(kSteps, knee),
            static_cast<float>(repository.Get("/Sim/Humanoid/Right/Knee/JointAngle").as_double()));
  EXPECT_GT(recording.value(kSteps, knee), 10.0f) << "the knee moved towards 40 degrees";
  EXPECT_EQ(recording.value(0, knee), 0.0f) << "frame 0 is the reset state";

  // Body poses: the head's pose channels point at its Position and OrientationQuaternion.
  const int bodies = static_cast<int>(recording.header["bodies"].size());
  EXPECT_EQ(bodies, simulation.model().physics()->body_count());
  const int head = simulation.model().physics()->FindBody("Humanoid/Middle/Head");
  ASSERT_GE(head, 0);
  const nlohmann::json& pose = recording.header["bodies"][head]["pose_channels"];
  ASSERT_EQ(pose.size(), 7u);
  const Eigen::Vector3d position = repository.Get("/Sim/Humanoid/Middle/Head/Position").as_vector3();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(recording.value(kSteps, pose[i]), static_cast<float>(position[i]));
  EXPECT_EQ(recording.channels[pose[3].get<int>()], "/Sim/Humanoid/Middle/Head/OrientationQuaternion.w");
}

TEST(RecorderTest, ContactsAreTheStepsConstraintContacts) {
  scene::Simulation simulation;
  SetUpStanding(simulation);
  Recorder recorder(simulation, RecordingSource{});
  std::vector<std::size_t> expected{0};
  for (int i = 0; i < 20; ++i) {
    simulation.Step();
    recorder.Sample();
    std::size_t made = 0;
    for (const physics::Contact& contact : simulation.physics().contacts()) made += !contact.excluded;
    expected.push_back(made);
  }
  const Recording recording = ParseRecording(recorder.Finish(), "test.orcsrec");
  for (int f = 0; f < recording.frame_count(); ++f) {
    EXPECT_EQ(recording.contact_offsets[f + 1] - recording.contact_offsets[f], expected[f]) << "frame " << f;
  }
  ASSERT_FALSE(recording.contacts.empty()) << "the feet stand on the floor";
  const int floor = simulation.model().physics()->FindBody("Floor");
  const RecordedContact& first = recording.contacts.front();
  EXPECT_TRUE(first.body1 == floor || first.body2 == floor);
  EXPECT_NEAR(first.position[1], 0.0f, 0.01f) << "on the floor, +Y up";
}

TEST(RecorderTest, HeaderCarriesTheEnvironmentsColoursAndShapes) {
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, ORCS_SOURCE_DIR "/scenarios/environments/example.xml", {}, {});
  simulation.Reset(0);
  Recorder recorder(simulation, RecordingSource{});
  const Recording recording = ParseRecording(recorder.Finish(), "test.orcsrec");
  bool found = false;
  for (const nlohmann::json& body : recording.header["bodies"]) {
    if (body["name"] != "SecondSphere") continue;
    found = true;
    EXPECT_EQ(body["geoms"][0]["shape"], "sphere");
    EXPECT_EQ(body["geoms"][0]["color"], nlohmann::json({255, 0, 0, 255})) << "color=\"red\" in example.xml";
    EXPECT_EQ(body["geoms"][0]["material"], "ABS");
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(recording.frame_count(), 1) << "frame 0 only";
}

// The original's textures are visual only; the header carries them for the viewer: the A-Series' servo cases
// (spec §2a: Right/Tibia "Dynamixel") and boards ("AccelBoard"), an XML object's texture, and no field where none.
TEST(RecorderTest, HeaderCarriesTexturesOnlyWhereThereAreAny) {
  test_support::TempDir dir;
  const std::string textured = dir.Write("textured.val", "/Sim/SecondSphere/Texture=Wood\n");  // as -ival does
  scene::Simulation simulation;
  scene::SetUpWorld(simulation, ORCS_SOURCE_DIR "/scenarios/environments/example.xml", {textured}, {});
  simulation.Reset(0);
  Recorder recorder(simulation, RecordingSource{});
  const Recording recording = ParseRecording(recorder.Finish(), "test.orcsrec");
  std::map<std::string, std::string> main_textures;  // body → its main geom's texture ("-" for none)
  int boards = 0;
  for (const nlohmann::json& body : recording.header["bodies"]) {
    const nlohmann::json& geoms = body["geoms"];
    main_textures[body["name"]] = geoms[0].value("texture", "-");
    for (const nlohmann::json& geom : geoms) boards += geom.value("texture", "") == "AccelBoard" ? 1 : 0;
  }
  EXPECT_EQ(main_textures["Humanoid/Right/Tibia"], "Dynamixel");
  EXPECT_EQ(main_textures["Humanoid/Right/Foot"], "-") << "no texture: no field";
  EXPECT_EQ(main_textures["SecondSphere"], "Wood") << "the object's /Texture value";
  EXPECT_EQ(boards, 16) << "both robots' eight boards";
}

}  // namespace
}  // namespace orcs::evaluation
