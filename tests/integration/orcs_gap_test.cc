// orcs-gap end to end (issue 6, "Done when"): pendulum runs made by `orcs-gap synth` with one hidden effect (and
// the spec's angle noise, σ 0.189°) are diagnosed by orcs-gap with its embedded broker and two real orcs-worker
// processes, choosing among the whole catalogue. The test reads report.json: the hidden effect must be named and
// the held-out gap must fall by at least half. Mistuned base parameters alone must give "no missing effect", and
// two hidden effects at once must name the stronger one. Every case runs on both engines (issue 20): the runs are
// made and diagnosed on ODE, and made and diagnosed on MuJoCo (orcs-gap --engine). Each diagnosis fits every
// candidate (about 6,000–11,000 replay jobs, 45–150 s on 2 cores). Every effect of the catalogue is named on
// this rig (docs/gap.md, "What it can and cannot tell"): since the coarse scan and the least-squares polish
// (issue 23) also backlash of 1°, 2° and 4°, Stribeck friction and LuGre friction.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "model/evaluation/recording_reader.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

using test_support::RunProcess;

const std::string kGap = ORCS_BINARY_DIR "/bin/orcs-gap";
const std::string kMotions = ORCS_SOURCE_DIR "/scenarios/motions/";

struct HiddenCase {
  const char* name;                  // test name
  std::vector<std::string> hidden;   // synth arguments: --effect NAME --set PATH=VALUE ...
  const char* expected;              // the effect orcs-gap must name; "" = none
  // The held-out gap after the diagnosis, at most this fraction of the model's as given, per engine. Backlash on
  // MuJoCo: the fit stops in a local minimum (width 1.6° of the hidden 3.4°; held-out 0.675° → 0.378°), though at
  // the true width the gap is the noise (0.186°). Global fits are issue 23.
  double ode_ratio = 0.5;
  double mujoco_ratio = 0.5;
  std::vector<std::string> options = {};  // more orcs-gap options
};

// The long cases of the hidden-effect families: each takes two to six minutes of both cores, so CI (scripts/test.sh)
// keeps the headline ones within its 40 minutes and `scripts/test.sh --long` (ORCS_LONG_TESTS=1) runs these too.
bool IsLongCase(const std::string& name) {
  static const std::set<std::string> kLong = {"StribeckFastFading", "LuGreStiffBristles", "TwoEffectsNameTheStronger",
                                              "LoadFriction", "StribeckSlowFading"};
  return kLong.count(name) != 0;
}
bool LongTestsWanted() {
  const char* wanted = std::getenv("ORCS_LONG_TESTS");
  return wanted != nullptr && std::string(wanted) == "1";
}

// Runs orcs-gap synth and a diagnosis on the pendulum rig.
class GapRunTest : public ::testing::Test {
 protected:
  // Synthesises the two identification runs on `engine`, diagnoses A with B held out on it, and returns
  // report.json.
  // `model`: a value file both commands start from ("" = the original's model); `fit_motion`: the fitted run.
  nlohmann::json Diagnose(const std::vector<std::string>& hidden, const std::string& engine,
                          const std::vector<std::string>& options = {}, const std::string& model = "",
                          const std::string& fit_motion = "pendulum_identification_a") {
    const std::string data = dir_.PathOf("data");
    std::vector<std::string> synth = {kGap,   "synth",  "--rig", "pendulum", "--engine", engine, "--motion",
                                      kMotions + fit_motion + ".csv",
                                      kMotions + "pendulum_identification_b.csv", "--out", data};
    synth.insert(synth.end(), hidden.begin(), hidden.end());
    if (!model.empty()) synth.insert(synth.end(), {"--model", model});
    const auto made = RunProcess(synth);
    EXPECT_EQ(made.exit_code, 0) << made.err;
    const std::string report = dir_.PathOf("report");
    std::vector<std::string> diagnose = {kGap, "--rig", "pendulum", "--engine", engine, "--measured",
                                         data + "/" + fit_motion + ".csv", "--holdout",
                                         data + "/pendulum_identification_b.csv", "--workers", "2", "--out", report};
    if (!model.empty()) diagnose.insert(diagnose.end(), {"--model", model});
    diagnose.insert(diagnose.end(), options.begin(), options.end());
    const auto diagnosed = RunProcess(diagnose);
    EXPECT_EQ(diagnosed.exit_code, 0) << diagnosed.err;
    std::ifstream in(report + "/report.json");
    return nlohmann::json::parse(in);
  }

  test_support::TempDir dir_;
};

class GapDiagnosisTest : public GapRunTest,
                         public ::testing::WithParamInterface<std::tuple<HiddenCase, const char*>> {};
using GapRaceTest = GapRunTest;

TEST_P(GapDiagnosisTest, NamesTheHiddenEffectAndHalvesTheHeldOutGap) {
  const auto& [c, engine] = GetParam();
  if (IsLongCase(c.name) && !LongTestsWanted()) GTEST_SKIP() << "a long case: scripts/test.sh --long runs it";
  const nlohmann::json report = Diagnose(c.hidden, engine);
  const nlohmann::json& verdict = report.at("verdict");
  std::cout << "orcs-gap verdict: " << verdict.at("text").get<std::string>() << "\n";  // for the test log's reader
  if (std::string(c.expected).empty()) {
    EXPECT_TRUE(verdict.at("effect").is_null()) << verdict.at("text");
    // The refit alone closes the gap of a mistuned model to the noise (σ 0.189°).
    EXPECT_LT(verdict.at("holdout_rms_refit").get<double>(), 0.3) << verdict.at("text");
    return;
  }
  ASSERT_FALSE(verdict.at("effect").is_null()) << verdict.at("text");
  EXPECT_EQ(verdict.at("effect").get<std::string>(), c.expected) << verdict.at("text");
  const double before = verdict.at("holdout_rms_before").get<double>();
  const double after = verdict.at("holdout_rms_after").get<double>();
  EXPECT_LE(after, (std::string(engine) == "ODE" ? c.ode_ratio : c.mujoco_ratio) * before) << verdict.at("text");
  // The fitted model switches the effect on, and the report lists every candidate with its fitted values.
  EXPECT_EQ(report.at("model").at("/Effects/" + std::string(c.expected) + "/Enabled"), "T");
  EXPECT_EQ(report.at("candidates").size(), 9u);
  // Named alone: no rival the held-out runs cannot tell from it.
  EXPECT_EQ(verdict.at("effects").size(), 1u) << verdict.at("text");
  // The winner ran its fit to the end; only candidates far behind the refit are abandoned (docs/gap.md).
  for (const nlohmann::json& candidate : report.at("candidates")) {
    if (candidate.at("model") == c.expected) {
      EXPECT_FALSE(candidate.at("fit").at("abandoned").get<bool>());
    }
  }
}

// The race (on by default): after 10 generations each candidate is polished and judged; one far behind the best or no
// better than nothing missing is abandoned, saving replays (docs/gap.md, "How a fit works"). BackEmf is the case
// that needs the polish: the refit absorbs it into friction and torque, so the scan's best point is no better than
// the refit, and judged there it was abandoned.
TEST_F(GapRaceTest, NamesBackEmfAndAbandonsCandidatesFarBehind) {
  const nlohmann::json report = Diagnose({"--effect", "BackEmf", "--set", "/Effects/BackEmf/NoLoadSpeed=5"}, "ODE");
  const nlohmann::json& verdict = report.at("verdict");
  std::cout << "orcs-gap verdict: " << verdict.at("text").get<std::string>() << "\n";  // for the test log's reader
  ASSERT_FALSE(verdict.at("effect").is_null()) << verdict.at("text");
  EXPECT_EQ(verdict.at("effect").get<std::string>(), "BackEmf") << verdict.at("text");
  EXPECT_LE(verdict.at("holdout_rms_after").get<double>(), 0.5 * verdict.at("holdout_rms_before").get<double>());
  EXPECT_EQ(report.at("criterion").at("abandon_share").get<double>(), 1.0);
  int abandoned = 0;
  for (const nlohmann::json& candidate : report.at("candidates")) {
    const nlohmann::json& fit = candidate.at("fit");
    if (fit.at("abandoned").get<bool>()) {
      ++abandoned;
      EXPECT_EQ(fit.at("generations").get<int>(), 10) << candidate.at("model");
    } else {
      EXPECT_LE(fit.at("generations").get<int>(), 40) << candidate.at("model");
    }
  }
  EXPECT_GT(abandoned, 0);
}

// --no-race fits every candidate to the end, and report.json says the race was off (and so the relaxed scan,
// with --no-relax-scan).
TEST_F(GapRaceTest, NoRaceIsRecordedAndAbandonsNothing) {
  const nlohmann::json report =
      Diagnose({"--effect", "TransportDelay", "--set", "/Effects/TransportDelay/Delay=0.04"}, "ODE",
               {"--no-race", "--no-relax-scan", "--generations", "12", "--effects", "DeadBand,Backlash"});
  EXPECT_TRUE(report.at("criterion").at("abandon_share").is_null());
  EXPECT_FALSE(report.at("criterion").at("relax_scan").get<bool>());
  EXPECT_EQ(report.at("criterion").at("islands").get<int>(), 0);  // --islands not given: none
  for (const nlohmann::json& candidate : report.at("candidates")) {
    EXPECT_FALSE(candidate.at("fit").at("abandoned").get<bool>()) << candidate.at("model");
    EXPECT_EQ(candidate.at("fit").at("generations").get<int>(), 12) << candidate.at("model");
  }
}

// --islands turns the race off unless --race is given: the race judges after 10 generations, before any island
// runs. Said on stderr before the runs are read (a missing run, exit 2, keeps this test short).
TEST(GapOptionsTest, IslandsTurnTheRaceOffUnlessRaceIsGiven) {
  test_support::TempDir dir;
  const auto diagnose = [&](std::vector<std::string> more) {
    std::vector<std::string> command = {kGap, "--rig", "pendulum", "--measured", dir.PathOf("missing.csv"),
                                        "--out", dir.PathOf("out")};
    command.insert(command.end(), more.begin(), more.end());
    return RunProcess(command);
  };
  const auto islands = diagnose({"--islands", "2"});
  EXPECT_EQ(islands.exit_code, 2);
  EXPECT_THAT(islands.err, HasSubstr("--islands turns the race off"));
  const auto raced = diagnose({"--islands", "2", "--race"});
  EXPECT_EQ(raced.exit_code, 2);
  EXPECT_THAT(raced.err, Not(HasSubstr("race")));
  EXPECT_THAT(diagnose({}).err, Not(HasSubstr("race")));  // no islands: the race stays on, nothing to say
}

// Replays stopped early (the default) leave every fit exactly as with every replay run to its end: the refit's and
// each candidate's values, errors, scores and replay counts are equal to the last bit (docs/gap.md, "How a fit
// works"), with real workers answering with the lower bounds they stopped at.
TEST_F(GapRunTest, ReplaysStoppedEarlyGiveTheSameDiagnosisBitForBit) {
  const std::vector<std::string> hidden = {"--effect", "TransportDelay", "--set", "/Effects/TransportDelay/Delay=0.04"};
  const std::vector<std::string> options = {"--generations", "12", "--effects", "DeadBand,TransportDelay"};
  const nlohmann::json early = Diagnose(hidden, "ODE", options);
  std::vector<std::string> whole_options = options;
  whole_options.push_back("--no-early-stop");
  const nlohmann::json whole = Diagnose(hidden, "ODE", whole_options);
  EXPECT_TRUE(early.at("criterion").at("early_stop").get<bool>());
  EXPECT_FALSE(whole.at("criterion").at("early_stop").get<bool>());
  // The relaxed scan is the pendulum rig's default; its polishes' replays always run to their end.
  EXPECT_TRUE(early.at("criterion").at("relax_scan").get<bool>());
  EXPECT_GT(early.at("cost").at("jobs_stopped_early").get<int>(), early.at("cost").at("jobs").get<int>() / 10);
  EXPECT_EQ(whole.at("cost").at("jobs_stopped_early").get<int>(), 0);
  EXPECT_EQ(early.at("cost").at("jobs"), whole.at("cost").at("jobs"));
  EXPECT_EQ(early.at("refit"), whole.at("refit"));
  EXPECT_EQ(early.at("candidates"), whole.at("candidates"));
  EXPECT_EQ(early.at("verdict"), whole.at("verdict"));
}

// The column `name` of an orcs-sim log (what orcs-gap synth writes), per row.
std::vector<double> LogColumn(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  int column = -1;
  std::vector<double> values;
  while (std::getline(in, line)) {
    if (line.rfind("# columns: ", 0) == 0) {
      std::istringstream names(line.substr(11));
      std::string field;
      for (int c = 0; std::getline(names, field, ','); ++c) {
        if (field == name) column = c;
      }
      continue;
    }
    if (line.empty() || line[0] == '#' || column < 0) continue;
    std::istringstream fields(line);
    std::string field;
    for (int c = 0; std::getline(fields, field, ','); ++c) {
      if (c == column) values.push_back(std::stod(field));
    }
  }
  return values;
}

// A mass off on a link, seen only through the accelerometers (issue 49): the A-Series swings its arms at the default
// torque, so the servos track alike whatever the right forearm weighs (0.15 kg hidden, the model's 0.071), but the
// trunk's boards feel the sway. The runs carry the eight boards' axes (synth --accelerometers) with an ADXL213's
// noise (scenarios/gap/aseries_accelerometers.val); orcs-gap compares them beside the angles and names LinkMass on
// that link. The per-run figures, angles only, show that the joints alone could not: their gap is the noise.
// MuJoCo both ways, 4 s of each motion, two candidates.
TEST(GapAccelerometerTest, AHiddenMassOffsetSeenOnlyByTheAccelerometersIsNamed) {
  test_support::TempDir dir;
  const std::string model = ORCS_SOURCE_DIR "/scenarios/gap/aseries_accelerometers.val";
  const std::string data = dir.PathOf("data");
  const auto made = RunProcess({kGap, "synth", "--rig", "aseries", "--engine", "MuJoCo", "--model", model,
                                "--accelerometers", "--duration", "4", "--motion", kMotions + "arm_movement.csv",
                                kMotions + "arm_swings.csv", "--set", "/Sim/Humanoid/Right/LowerArm/Mass=0.15",
                                "--seed", "49", "--out", data});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  ASSERT_FALSE(LogColumn(data + "/arm_swings.csv", "/Sim/Humanoid/ABSR/AccelAxis1").empty());
  const std::string report_dir = dir.PathOf("report");
  const auto diagnosed =
      RunProcess({kGap, "--rig", "aseries", "--engine", "MuJoCo", "--model", model, "--measured",
                  data + "/arm_movement.csv", "--holdout", data + "/arm_swings.csv", "--effects",
                  "LinkMass,TransportDelay", "--workers", "2", "--out", report_dir});
  ASSERT_EQ(diagnosed.exit_code, 0) << diagnosed.err;
  std::ifstream in(report_dir + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& verdict = report.at("verdict");
  std::cout << "orcs-gap verdict: " << verdict.at("text").get<std::string>() << "\n";  // for the test log's reader
  ASSERT_FALSE(verdict.at("effect").is_null()) << verdict.at("text");
  EXPECT_EQ(verdict.at("effect").get<std::string>(), "LinkMass") << verdict.at("text");
  EXPECT_THAT(verdict.at("text").get<std::string>(), HasSubstr("the mass of Right/LowerArm is"));
  EXPECT_NEAR(std::stod(report.at("model").at("/Sim/Humanoid/Right/LowerArm/Mass").get<std::string>()), 0.15, 0.02);
  EXPECT_LE(verdict.at("holdout_rms_after").get<double>(), 0.5 * verdict.at("holdout_rms_before").get<double>())
      << verdict.at("text");
  // The angles alone: every run's RMS under the model as given is the angle sensor's noise (σ 0.189°).
  for (const nlohmann::json& run : report.at("gap").at("before").at("runs")) {
    EXPECT_LT(run.at("rms").get<double>(), 0.2) << run.at("run");
  }
  EXPECT_GT(verdict.at("holdout_rms_before").get<double>(), 0.3) << "the accelerometers show the gap";
}

// Ties (docs/gap.md, "When two effects explain the data"): a Stribeck friction at LuGre's own Stribeck velocity
// (0.1 rad/s) is, in steady sliding, LuGre's curve, and these runs never show the bristles' memory: both explain the
// held-out run at the noise, and the verdict names both rather than one with a convincing number. Every probe
// motion is replayed under the two fitted models; here none differs by more than the noise, and the verdict says
// so. The probe that came closest can still be made with synth --probe.
TEST_F(GapRunTest, AFrictionTwoEffectsReproduceIsATieThatNamesBothAndSaysWhetherAProbeTellsThemApart) {
  const std::vector<std::string> hidden = {"--effect", "Stribeck", "--set", "/Effects/Stribeck/BreakawayTorque=0.1",
                                           "--set",    "/Effects/Stribeck/Velocity=0.1", "--seed", "77"};
  const nlohmann::json report = Diagnose(hidden, "ODE", {"--effects", "Stribeck,LuGre"});
  const nlohmann::json& verdict = report.at("verdict");
  const std::string text = verdict.at("text").get<std::string>();
  std::cout << "orcs-gap verdict: " << text << "\n";
  EXPECT_TRUE(verdict.at("tie").get<bool>()) << text;
  EXPECT_THAT(verdict.at("effects").get<std::vector<std::string>>(),
              ::testing::UnorderedElementsAre("Stribeck", "LuGre"))
      << text;
  EXPECT_THAT(text, HasSubstr("cannot tell them apart"));
  EXPECT_LT(verdict.at("holdout_rms_after").get<double>(), 0.21) << text;  // the noise, σ 0.189°
  ASSERT_EQ(verdict.at("rivals").size(), 1u) << text;
  EXPECT_LE(verdict.at("rivals")[0].at("holdout_ratio").get<double>(), 1.118) << text;
  const nlohmann::json& apart = verdict.at("tell_apart");
  EXPECT_LT(apart.at("difference_deg").get<double>(), apart.at("noise_deg").get<double>()) << text;
  EXPECT_THAT(text, HasSubstr("None of orcs's probe motions tells them apart"));
  EXPECT_EQ(apart.at("motor").get<std::string>(), "Motor");

  const std::string probe = apart.at("probe").get<std::string>();
  std::vector<std::string> synth = {kGap, "synth", "--rig", "pendulum", "--probe", probe, "--probe-motor", "Motor",
                                    "--out", dir_.PathOf("probe")};
  synth.insert(synth.end(), hidden.begin(), hidden.end());
  const auto made = RunProcess(synth);
  ASSERT_EQ(made.exit_code, 0) << made.err;
  EXPECT_TRUE(std::filesystem::file_size(dir_.PathOf("probe") + "/motions/" + probe + ".csv") > 0);
  EXPECT_GT(LogColumn(dir_.PathOf("probe") + "/" + probe + ".csv", "/Sim/Pendulum/Motor/JointAngle").size(), 100u);
}

// Three recordings per measured run in replays/ for orcs-view: the fitted model's replay, the given model's, and the
// measured run posed kinematically, whose JointAngle is the measured angle. A small diagnosis: short runs, one
// candidate, two generations.
TEST(GapReplaysTest, EveryRunGetsItsFittedGivenAndMeasuredRecording) {
  test_support::TempDir dir;
  const std::string data = dir.PathOf("data");
  const auto made = RunProcess({kGap, "synth", "--rig", "pendulum", "--motion", kMotions + "pendulum_identification_a.csv",
                                kMotions + "pendulum_identification_b.csv", "--duration", "2", "--effect",
                                "TransportDelay", "--set", "/Effects/TransportDelay/Delay=0.04", "--out", data});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const std::string report = dir.PathOf("report");
  dir.Write("report/replays/stale.orcsrec", "an earlier report's");
  const auto diagnosed = RunProcess({kGap, "--rig", "pendulum", "--measured", data + "/pendulum_identification_a.csv",
                                     "--holdout", data + "/pendulum_identification_b.csv", "--workers", "2",
                                     "--effects", "TransportDelay", "--generations", "2", "--out", report});
  ASSERT_EQ(diagnosed.exit_code, 0) << diagnosed.err;
  // Issue 21: it says what it fits while it works, and how each fit came out.
  EXPECT_THAT(diagnosed.err, HasSubstr("orcs-gap: fitting the model's own parameters (refit)"));
  EXPECT_THAT(diagnosed.err, HasSubstr("orcs-gap: fitting TransportDelay"));
  EXPECT_THAT(diagnosed.err, HasSubstr("orcs-gap: TransportDelay fitted: held-out gap "));
  EXPECT_FALSE(std::filesystem::exists(report + "/replays/stale.orcsrec"));
  // Issue 23: every run's gap, fitted and held out, as RMS and as the BAM project's mean absolute error (mrad),
  // which is at most the RMS (in mrad).
  std::ifstream json(report + "/report.json");
  const nlohmann::json document = nlohmann::json::parse(json);
  for (const char* snapshot : {"before", "refit", "after"}) {
    const nlohmann::json& runs = document.at("gap").at(snapshot).at("runs");
    ASSERT_EQ(runs.size(), 2u) << snapshot;
    EXPECT_EQ(runs[0].at("run"), "pendulum_identification_a");
    EXPECT_FALSE(runs[0].at("held_out").get<bool>());
    EXPECT_EQ(runs[1].at("run"), "pendulum_identification_b");
    EXPECT_TRUE(runs[1].at("held_out").get<bool>());
    for (const nlohmann::json& run : runs) {
      const double mae = run.at("mean_absolute_mrad").get<double>(), rms = run.at("rms").get<double>();
      EXPECT_GT(mae, 0.0) << snapshot;
      EXPECT_LE(mae, rms * 1000.0 * M_PI / 180.0 + 1e-9) << snapshot;
    }
  }
  std::ifstream md(report + "/report.md");
  const std::string markdown((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_THAT(markdown, HasSubstr("## Per run: mean absolute error / RMS"));
  EXPECT_THAT(markdown, ::testing::ContainsRegex("\\| pendulum_identification_b \\| held out \\| [0-9.]+ mrad / [0-9.]+°"));
  for (const std::string run : {"pendulum_identification_a", "pendulum_identification_b"}) {
    const std::vector<double> measured =
        LogColumn(data + "/" + run + ".csv", "/Sim/Pendulum/Motor/JointAngle");
    ASSERT_GT(measured.size(), 100u) << run;
    for (const char* suffix : {".orcsrec", ".given.orcsrec"}) {
      const evaluation::Recording replay = evaluation::ReadRecording(report + "/replays/" + run + suffix);
      EXPECT_EQ(replay.frame_count(), static_cast<int>(measured.size())) << run << suffix;  // frame 0 and every step
    }
    const evaluation::Recording recording = evaluation::ReadRecording(report + "/replays/" + run + ".measured.orcsrec");
    ASSERT_EQ(recording.frame_count(), static_cast<int>(measured.size())) << run;
    const int channel = recording.FindChannel("/Sim/Pendulum/Motor/JointAngle");
    ASSERT_GE(channel, 0);
    for (std::size_t row : {std::size_t{0}, std::size_t{1}, measured.size() / 3, measured.size() / 2,
                            measured.size() - 1}) {
      EXPECT_NEAR(recording.times[row], 0.01 * static_cast<double>(row), 1e-9) << run << " row " << row;
      // The pendulum's motor turns −150°…150°: the measured angles lie inside, so no clamping here.
      EXPECT_NEAR(recording.value(static_cast<int>(row), channel), measured[row],
                  1e-6 * std::max(1.0, std::abs(measured[row])))
          << run << " row " << row;
    }
  }
}

// A representative subset of the hidden-effect family (docs/gap.md, "How often it is right"; the whole family is
// scripts/gap_family.py), each case on one engine — the two engines take turns down the list, so that both
// diagnose several effects (a diagnosis takes one to two minutes). ORCS_GAP_BOTH_ENGINES=1 runs every case on both;
// the long ones (IsLongCase) only run with ORCS_LONG_TESTS=1.
std::vector<std::tuple<HiddenCase, const char*>> HiddenCasesOnEngines() {
  const std::vector<HiddenCase> cases = {
        HiddenCase{"TransportDelay", {"--effect", "TransportDelay", "--set", "/Effects/TransportDelay/Delay=0.04"},
                   "TransportDelay"},
        HiddenCase{"DeadBand", {"--effect", "DeadBand", "--set", "/Effects/DeadBand/Margin=1.7"}, "DeadBand"},
        // Issue 49: a Stribeck velocity higher than the others here; its fit used to stop at a bound (breakaway
        // torque at the top of its range, velocity a tenth of the truth) and LuGre was named.
        HiddenCase{"StribeckFastFading",
                   {"--effect", "Stribeck", "--set", "/Effects/Stribeck/BreakawayTorque=0.2", "--set",
                    "/Effects/Stribeck/Velocity=0.8"},
                   "Stribeck"},
        // Issue 49: stiff bristles; the fits of the time named LoadFriction.
        HiddenCase{"LuGreStiffBristles",
                   {"--effect", "LuGre", "--set", "/Effects/LuGre/StictionTorque=0.2", "--set",
                    "/Effects/LuGre/CoulombTorque=0.08", "--set", "/Effects/LuGre/BristleStiffness=300"},
                   "LuGre"},
        HiddenCase{"MistunedBaseOnly",
                   {"--set", "/AngularMotor/PID/Proportional=14", "--set", "/AngularMotor/FMaxFactor=0.9"},
                   ""},
        HiddenCase{"TwoEffectsNameTheStronger",
                   {"--effect", "TransportDelay", "--set", "/Effects/TransportDelay/Delay=0.04", "--effect", "DeadBand",
                    "--set", "/Effects/DeadBand/Margin=0.6"},
                   "TransportDelay"}};
  const char* both = std::getenv("ORCS_GAP_BOTH_ENGINES");
  const bool every_engine = both != nullptr && std::string(both) == "1";
  std::vector<std::tuple<HiddenCase, const char*>> on_engines;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    if (every_engine || i % 2 == 0) on_engines.emplace_back(cases[i], "ODE");
    if (every_engine || i % 2 == 1) on_engines.emplace_back(cases[i], "MuJoCo");
  }
  return on_engines;
}

INSTANTIATE_TEST_SUITE_P(
    HiddenEffects, GapDiagnosisTest, ::testing::ValuesIn(HiddenCasesOnEngines()),
    [](const ::testing::TestParamInfo<std::tuple<HiddenCase, const char*>>& param) {
      return std::string(std::get<0>(param.param).name) + "_" + std::get<1>(param.param);
    });

// The physical servo model (issue 23, docs/gap.md "On the physical servo model"): runs synthesised under the AX-12's
// servo parameters with a hidden effect, fitted on servo_identification_a (A with a limp swing, which tells
// back-EMF from viscous friction) and scored on B. ODE only: the servo model is the same code on both engines.
class GapServoDiagnosisTest : public GapRunTest, public ::testing::WithParamInterface<HiddenCase> {};

TEST_P(GapServoDiagnosisTest, NamesTheHiddenEffectAndHalvesTheHeldOutGap) {
  const HiddenCase& c = GetParam();
  if (IsLongCase(c.name) && !LongTestsWanted()) GTEST_SKIP() << "a long case: scripts/test.sh --long runs it";
  const nlohmann::json report =
      Diagnose(c.hidden, "ODE", c.options, ORCS_SOURCE_DIR "/scenarios/values/servo_ax12.val", "servo_identification_a");
  const nlohmann::json& verdict = report.at("verdict");
  std::cout << "orcs-gap verdict: " << verdict.at("text").get<std::string>() << "\n";  // for the test log's reader
  ASSERT_FALSE(verdict.at("effect").is_null()) << verdict.at("text");
  EXPECT_EQ(verdict.at("effect").get<std::string>(), c.expected) << verdict.at("text");
  EXPECT_LE(verdict.at("holdout_rms_after").get<double>(), c.ode_ratio * verdict.at("holdout_rms_before").get<double>())
      << verdict.at("text");
  // What the limp swing is for: back-EMF and viscous friction each fitted near their values (1.942 V·s/rad and
  // 0.02 N·m·s/rad in servo_ax12.val); without it the fit traded one for the other (2.05 and 0.006).
  EXPECT_NEAR(std::stod(report.at("model").at("/Servo/ViscousFriction").get<std::string>()), 0.02, 0.004);
  EXPECT_NEAR(std::stod(report.at("model").at("/Servo/BackEmfConstant").get<std::string>()), 1.942, 0.04);
  EXPECT_EQ(report.at("verdict").at("effects").size(), 1u) << verdict.at("text");
  // The fitted value of the hidden effect's first parameter lies within 20 % of the hidden one.
  const std::string& set = c.hidden.at(3);  // after "--effect" NAME "--set": PATH=VALUE
  const std::string path = set.substr(0, set.find('='));
  EXPECT_NEAR(std::stod(report.at("model").at(path).get<std::string>()), std::stod(set.substr(set.find('=') + 1)),
              0.2 * std::stod(set.substr(set.find('=') + 1)))
      << path;
}

INSTANTIATE_TEST_SUITE_P(
    ServoHiddenEffects, GapServoDiagnosisTest,
    ::testing::Values(
        // Issue 49's three: a load friction whose fit stopped at less than half its coefficient while BackDrive was
        // named; a backlash of 1.5° fitted at 1.19°; a Stribeck friction with a low velocity named as LuGre.
        HiddenCase{"LoadFriction", {"--effect", "LoadFriction", "--set", "/Effects/LoadFriction/Coefficient=0.3"},
                   "LoadFriction"},
        HiddenCase{"Backlash1p5Degrees", {"--effect", "Backlash", "--set", "/Effects/Backlash/Width=1.5"}, "Backlash"},
        HiddenCase{"StribeckSlowFading",
                   {"--effect", "Stribeck", "--set", "/Effects/Stribeck/BreakawayTorque=0.25", "--set",
                    "/Effects/Stribeck/Velocity=0.08"},
                   "Stribeck"}),
    [](const ::testing::TestParamInfo<HiddenCase>& param) { return std::string(param.param.name); });

// ---------------------------------------------------------------------------------------------------------------
// The physical servo model on real logs (issue 23): the firmware gain is each run's input.

namespace servo {

const std::string kXl330 = ORCS_SOURCE_DIR "/scenarios/gap/xl330/";

// A log of the XL330 rig's format: `gain` in the first comment (none when empty), `rows` rows of 5 ms.
std::string Xl330Log(const std::string& gain, int rows) {
  std::ostringstream log;
  log << "# XL330 pendulum log: motor=xl330" << (gain.empty() ? "" : " firmware_kp=" + gain) << "\n"
      << "time_s,goal_deg,position_deg,speed_deg_s,load,input_volts,temperature_c,torque_enable\n";
  for (int i = 0; i < rows; ++i) log << i * 0.005 << ",10,0,0,0,7.4,30," << (i < rows / 2 ? 1 : 0) << "\n";
  return log.str();
}

test_support::ProcessResult Gap(const std::vector<std::string>& runs, const std::string& mapping,
                                const std::string& out) {
  std::vector<std::string> command = {kGap, "--rig", "pendulum", "--pole-mass", "0.6533", "--pole-length", "0.15",
                                      "--model", kXl330 + "model.val", "--mapping", mapping, "--measured"};
  command.insert(command.end(), runs.begin(), runs.end());
  command.insert(command.end(), {"--workers", "1", "--generations", "1", "--effects", "Stribeck", "--out", out});
  return RunProcess(command);
}

// The column `name` of an orcs-gap trace (traces/<run>.<motor>.csv: a header line, then one row per measured row).
std::vector<double> TraceColumn(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::istringstream names(line);
  std::string field;
  int column = -1;
  for (int c = 0; std::getline(names, field, ','); ++c) {
    if (field == name) column = c;
  }
  std::vector<double> values;
  while (column >= 0 && std::getline(in, line)) {
    std::istringstream fields(line);
    for (int c = 0; std::getline(fields, field, ','); ++c) {
      if (c == column) values.push_back(std::stod(field));
    }
  }
  return values;
}

// --loss absolute through the real broker and workers: the report says so, and the refit's score is the mean
// absolute error of the held-out run's refit trace (traces/b.Motor.csv) over the rows after the first, as compared.
TEST(GapServoTest, TheAbsoluteLossScoresTheHeldOutRunByItsMeanAbsoluteError) {
  test_support::TempDir dir;
  const std::vector<std::string> runs = {dir.Write("a.csv", Xl330Log("100", 40)), dir.Write("b.csv", Xl330Log("400", 60))};
  const std::string out = dir.PathOf("out");
  std::vector<std::string> command = {kGap, "--rig", "pendulum", "--pole-mass", "0.6533", "--pole-length", "0.15",
                                      "--model", kXl330 + "model.val", "--mapping", kXl330 + "mapping.json",
                                      "--measured", runs[0], runs[1], "--workers", "1", "--generations", "1",
                                      "--effects", "Stribeck", "--loss", "absolute", "--out", out};
  const auto result = RunProcess(command);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["criterion"]["loss"], "absolute");
  const std::vector<double> measured = TraceColumn(out + "/traces/b.Motor.csv", "measured");
  const std::vector<double> refit = TraceColumn(out + "/traces/b.Motor.csv", "refit");
  ASSERT_EQ(measured.size(), 60u);
  ASSERT_EQ(refit.size(), 60u);
  double absolute = 0.0, squares = 0.0;
  for (std::size_t row = 1; row < measured.size(); ++row) {
    absolute += std::abs(refit[row] - measured[row]);
    squares += (refit[row] - measured[row]) * (refit[row] - measured[row]);
  }
  absolute /= 59.0;
  ASSERT_GT(absolute, 0.1);
  EXPECT_NEAR(report["refit"]["score"].get<double>(), absolute, 1e-9 * absolute + 1e-12);
  // The RMS figure beside it is still the RMS.
  EXPECT_NEAR(report["refit"]["holdout_rms"].get<double>(), std::sqrt(squares / 59.0), 1e-9);

  command.back() = dir.PathOf("refused");
  command[command.size() - 3] = "max";
  const auto refused = RunProcess(command);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_THAT(refused.err, HasSubstr("--loss"));
}

// An effect the model switches on is refitted with the base; naming it as a candidate is refused before any fit.
TEST(GapServoTest, AnEffectTheModelSwitchesOnIsNoCandidate) {
  test_support::TempDir dir;
  std::ifstream shipped(kXl330 + "model.val");
  std::stringstream text;
  text << shipped.rdbuf() << "/Effects/GravityLoadFriction/Enabled=T\n";
  const std::string model = dir.Write("m3.val", text.str());
  std::vector<std::string> command = {kGap, "--rig", "pendulum", "--model", model,
                                      "--mapping", kXl330 + "mapping.json", "--measured",
                                      dir.Write("a.csv", Xl330Log("100", 40)), dir.Write("b.csv", Xl330Log("400", 40)),
                                      "--workers", "1", "--effects", "GravityLoadFriction", "--out", dir.PathOf("out")};
  const auto result = RunProcess(command);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr("orcs-gap: --effects: 'GravityLoadFriction' is switched on in the model already"));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 2) << "its progress line and the error\n"
                                                                        << result.err;
}

TEST(GapServoTest, ARunWithoutItsFirmwareGainIsOneLineNamingFileAndColumnExit2) {
  test_support::TempDir dir;
  // The shipped mapping reads the gain from the header: a log without it cannot be replayed by the servo model.
  const std::string without = dir.Write("no_gain.csv", Xl330Log("", 40));
  const auto missing = Gap({without, dir.Write("ok.csv", Xl330Log("100", 40))}, kXl330 + "mapping.json", dir.PathOf("a"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.err, HasSubstr(without + ": no 'firmware_kp=' in the comment lines"));
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  // A mapping without a gain at all: the servo model says what it needs.
  std::string mapping_text;
  {
    std::ifstream in(kXl330 + "mapping.json");
    std::stringstream buffer;
    buffer << in.rdbuf();
    mapping_text = buffer.str();
  }
  mapping_text.replace(mapping_text.find("\"firmware_kp\""), std::string("\"firmware_kp\": {\"header\": \"firmware_kp\"},").size(), "");
  const std::string no_gain_mapping = dir.Write("no_gain.json", mapping_text);
  const std::string run = dir.Write("run.csv", Xl330Log("100", 40));
  const auto unmapped = Gap({run, dir.Write("run2.csv", Xl330Log("100", 41))}, no_gain_mapping, dir.PathOf("b"));
  EXPECT_EQ(unmapped.exit_code, 2);
  EXPECT_THAT(unmapped.err, HasSubstr(run + ": no firmware gain: the servo model (/Servo/Enabled) needs the P gain"));
  EXPECT_EQ(std::count(unmapped.err.begin(), unmapped.err.end(), '\n'), 1) << unmapped.err;
}

TEST(GapServoTest, AGainThatChangesWithinARunIsOneLineNamingFileLineAndColumnExit2) {
  test_support::TempDir dir;
  std::string log = Xl330Log("100", 40);
  const std::string mapping = dir.Write(
      "by_column.json",
      R"({"agent": "Pendulum", "time": {"column": "time_s"}, "firmware_kp": {"column": "temperature_c"},
          "channels": [{"motor": "Motor", "desired_angle": {"column": "goal_deg"},
          "desired_torque": {"column": "torque_enable"}, "joint_angle": {"column": "position_deg"}}]})");
  log.replace(log.rfind(",7.4,30,"), 8, ",7.4,31,");  // the last row says another gain
  const std::string changing = dir.Write("changing.csv", log);
  const auto result = Gap({changing, dir.Write("ok.csv", Xl330Log("100", 40))}, mapping, dir.PathOf("out"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.err, HasSubstr(changing + ":42: temperature_c: the firmware gain changes within the run, from 30"));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

}  // namespace servo

}  // namespace
}  // namespace orcs
