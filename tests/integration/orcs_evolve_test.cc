// `orcs-batch evolve` as users run it: the real program with its embedded broker and two local orcs-worker
// processes on 127.0.0.1, evolving a tiny walking oscillator (half a second, two parameter sets, five genomes, two
// generations). Checks the output folder, that the winner replays with orcs-sim to the same bits, that an
// interrupted and resumed run equals an uninterrupted one, that bad input stops with exit 2 before anything runs,
// and the plot script.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <optional>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "model/evaluation/recording_reader.h"
#include "tests/support/background_process.h"
#include "tests/support/process.h"
#include "tests/support/temp_dir.h"

namespace orcs {
namespace {

namespace fs = std::filesystem;
using test_support::ProcessResult;
using test_support::RunProcess;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kBin = ORCS_BINARY_DIR "/bin/";

// A two-neuron oscillator rocking and swinging the legs (the controller of scenarios/evolution/walk_oscillator.json),
// 10 genes; `duration` seconds under two randomised parameter sets; five genomes, two generations, the winner
// validated on two fresh seeds.
std::string WalkScenario(double duration) {
  return R"({
  "name": "tiny-walk",
  "genome": [0.01, 1.0978, 0.0698, -0.0698, 1.0978, 0.05, -0.05, 0.05, 0.0, 0.0],
  "duration": )" +
         std::to_string(duration) + R"(,
  "controller": {
    "type": "network",
    "transfer": "tanh",
    "inputs": [],
    "neurons": [
      {"name": "osc1", "bias": null},
      {"name": "osc2", "bias": 0},
      {"name": "hip_rock", "bias": 0, "transfer": "linear"},
      {"name": "ankle_rock", "bias": 0, "transfer": "linear"},
      {"name": "hip_swing", "bias": 0, "transfer": "linear"},
      {"name": "ankle_swing", "bias": 0, "transfer": "linear"},
      {"name": "knee_bend", "bias": 0, "transfer": "linear"}
    ],
    "synapses": [
      {"from": "osc1", "to": "osc1", "weight": null},
      {"from": "osc2", "to": "osc1", "weight": null},
      {"from": "osc1", "to": "osc2", "weight": null},
      {"from": "osc2", "to": "osc2", "weight": null},
      {"from": "osc1", "to": "hip_rock", "weight": null},
      {"from": "osc1", "to": "ankle_rock", "weight": null},
      {"from": "osc2", "to": "hip_swing", "weight": null},
      {"from": "osc2", "to": "ankle_swing", "weight": null},
      {"from": "osc1", "to": "knee_bend", "weight": null}
    ],
    "outputs": [
      {"neuron": "hip_rock", "value": "Right/HipPitch/DesiredAngle"},
      {"neuron": "hip_rock", "value": "Left/HipPitch/DesiredAngle"},
      {"neuron": "ankle_rock", "value": "Right/AnklePitch/DesiredAngle"},
      {"neuron": "ankle_rock", "value": "Left/AnklePitch/DesiredAngle"},
      {"neuron": "hip_swing", "value": "Right/HipYaw/DesiredAngle"},
      {"neuron": "hip_swing", "value": "Left/HipYaw/DesiredAngle"},
      {"neuron": "ankle_swing", "value": "Right/AnkleYaw/DesiredAngle"},
      {"neuron": "ankle_swing", "value": "Left/AnkleYaw/DesiredAngle"},
      {"neuron": "knee_bend", "value": "Right/Knee/DesiredAngle"},
      {"neuron": "knee_bend", "value": "Left/Knee/DesiredAngle"}
    ]
  },
  "fitness": {
    "terms": [
      {"type": "distance", "name": "forward", "body": "Middle/UpperBody", "axis": "z", "weight": 10},
      {"type": "upright_time", "body": "Middle/Head", "min_height": 0.25, "weight": 0.1}
    ],
    "aggregate": "mean"
  },
  "randomisation": {"sets": 2, "default_motor_model": true},
  "evolution": {
    "bounds": [[-0.05, 0.05], [0.8, 1.5], [-0.5, 0.5], [-0.5, 0.5], [0.8, 1.5],
               [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15], [-0.15, 0.15]],
    "algorithm": "cmaes",
    "population": 5,
    "generations": 2,
    "seed": 1,
    "validate": 2
  },
  "log": ["/Sim/Humanoid/Middle/UpperBody/Position"]
})";
}

// A file's text, or "" while it does not exist yet.
std::string ReadIfThere(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

// fitness.csv without its last column (seconds: wall clock, not part of the search).
std::vector<std::string> WithoutSeconds(const std::string& csv) {
  std::vector<std::string> lines = Lines(csv);
  for (std::string& line : lines) line = line.substr(0, line.rfind(','));
  return lines;
}

// Exit 2 and exactly one line on stderr, "orcs-batch: ...".
void ExpectOneLineBadInput(const ProcessResult& result) {
  EXPECT_EQ(result.exit_code, 2) << result.out << result.err;
  EXPECT_THAT(result.err, StartsWith("orcs-batch: "));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

class OrcsEvolveTest : public ::testing::Test {
 protected:
  // orcs-batch evolve SCENARIO ARGUMENTS... on two local workers, no plot.
  ProcessResult Evolve(const std::string& scenario, std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), {kBin + "orcs-batch", "evolve", scenario, "--workers", "2", "--no-plot"});
    return RunProcess(arguments);
  }
  std::string Scenario(double duration = 0.5) { return dir_.Write("walk.json", WalkScenario(duration)); }
  std::string Out(const std::string& name) const { return dir_.PathOf(name); }
  nlohmann::json Checkpoint(const std::string& folder) const {
    return nlohmann::json::parse(dir_.Read(folder + "/checkpoint.json"));
  }
  TempDir dir_;
};

TEST_F(OrcsEvolveTest, RunWritesItsFolderAndTheWinnerReplaysWithOrcsSimToTheSameBits) {
  const std::string scenario = Scenario();
  const std::string out = Out("run");
  const ProcessResult run = Evolve(scenario, {"--out", out});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_THAT(run.out, HasSubstr("(the same bits)"));
  EXPECT_THAT(run.err, HasSubstr("generation 2/2"));

  // fitness.csv: generations 0, 1, 2 of five genomes each.
  const std::vector<std::string> csv = Lines(dir_.Read(out + "/fitness.csv"));
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[0], "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds");
  for (int g = 0; g <= 2; ++g) EXPECT_THAT(csv[g + 1], StartsWith(std::to_string(g) + ",5,")) << csv[g + 1];
  const nlohmann::json progress = nlohmann::json::parse(dir_.Read(out + "/progress.json"));
  EXPECT_EQ(progress["command"], "evolve");
  EXPECT_EQ(progress["state"], "finished");
  EXPECT_EQ(progress["last_generation"], 2);
  EXPECT_EQ(progress["generations"], 2);

  // checkpoint.json and best_genome.json agree on the champion.
  const nlohmann::json checkpoint = Checkpoint(out);
  EXPECT_EQ(checkpoint["history"].size(), 3u);
  const nlohmann::json champion = checkpoint["champion"];
  ASSERT_EQ(champion["genome"].size(), 10u);
  EXPECT_EQ(nlohmann::json::parse(dir_.Read(out + "/best_genome.json")), champion["genome"]);

  // best/: the winner on the run's seed, then the two validation seeds, with logs.
  const std::vector<std::string> results = Lines(dir_.Read(out + "/best/results.jsonl"));
  ASSERT_EQ(results.size(), 3u);
  const nlohmann::json winner = nlohmann::json::parse(results[0]);
  EXPECT_EQ(winner["id"], "winner");
  EXPECT_EQ(winner["role"], "winner");
  EXPECT_EQ(winner["seed"], 1);
  EXPECT_EQ(winner["status"], "ok");
  EXPECT_EQ(winner["fitness"].get<double>(), champion["fitness"].get<double>());
  for (int v = 1; v <= 2; ++v) {
    const nlohmann::json line = nlohmann::json::parse(results[v]);
    EXPECT_EQ(line["id"], "validate-" + std::to_string(v));
    EXPECT_EQ(line["role"], "validation");
    EXPECT_EQ(line["seed"], 1 + v);
  }
  ASSERT_TRUE(fs::is_directory(out + "/best/logs"));
  EXPECT_FALSE(fs::is_empty(out + "/best/logs"));

  // best/recordings/winner.orcsrec: the winner's replay (set 0) for orcs-view; the validation runs are not recorded.
  EXPECT_EQ(winner["recording"], "recordings/winner.orcsrec");
  const evaluation::Recording recording = evaluation::ReadRecording(out + "/best/recordings/winner.orcsrec");
  EXPECT_EQ(recording.frame_count(), 51);  // half a second at 10 ms, and frame 0
  EXPECT_EQ(recording.header["source"]["genome"], champion["genome"]);
  EXPECT_FALSE(fs::exists(out + "/best/recordings/validate-1.orcsrec"));
  EXPECT_THAT(run.out, HasSubstr("orcs-view " + out));

  // orcs-sim replays best_genome.json on the run's seed to the champion's fitness, bit for bit.
  const ProcessResult sim = RunProcess(
      {kBin + "orcs-sim", "--scenario", scenario, "--genome", "@" + out + "/best_genome.json", "--seed", "1"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(nlohmann::json::parse(sim.out)["fitness"].get<double>(), champion["fitness"].get<double>());
}

// evolve --engine MuJoCo: every job runs on MuJoCo, the replay line it prints names the engine and replays the
// winner to its bits; a resume must be on the engine the run was made on.
TEST_F(OrcsEvolveTest, ARunOnMujocoReplaysOnMujocoAndResumesOnlyThere) {
  const std::string scenario = Scenario();
  const std::string out = Out("mujoco");
  const ProcessResult run = Evolve(scenario, {"--out", out, "--engine", "MuJoCo", "--validate", "0"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_THAT(run.out, HasSubstr("--seed 1 --engine MuJoCo"));
  const nlohmann::json winner = nlohmann::json::parse(Lines(dir_.Read(out + "/best/results.jsonl")).at(0));
  EXPECT_EQ(winner["engine"], "MuJoCo");
  const ProcessResult sim = RunProcess({kBin + "orcs-sim", "--scenario", scenario, "--genome",
                                        "@" + out + "/best_genome.json", "--seed", "1", "--engine", "MuJoCo"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(nlohmann::json::parse(sim.out)["fitness"].get<double>(), winner["fitness"].get<double>());
  const ProcessResult on_ode = Evolve(scenario, {"--resume", out, "--generations", "3", "--engine", "ODE"});
  ExpectOneLineBadInput(on_ode);
  // Without --engine the resume takes the engine from the checkpoint, as every other setting.
  const ProcessResult on_mujoco = Evolve(scenario, {"--resume", out, "--generations", "3", "--validate", "0"});
  EXPECT_EQ(on_mujoco.exit_code, 0) << on_mujoco.err;
  EXPECT_THAT(on_mujoco.out, HasSubstr("--engine MuJoCo"));
}

TEST_F(OrcsEvolveTest, AnInterruptedAndResumedRunEqualsAnUninterruptedOne) {
  const std::string scenario = Scenario();
  const ProcessResult first = Evolve(scenario, {"--generations", "1", "--out", Out("a")});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(Lines(dir_.Read(Out("a") + "/fitness.csv")).size(), 3u) << "generations 0 and 1";
  const ProcessResult resumed = Evolve(scenario, {"--resume", Out("a"), "--generations", "2"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("resuming after generation 1"));

  const ProcessResult whole = Evolve(scenario, {"--generations", "2", "--out", Out("b")});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  const std::vector<std::string> resumed_csv = WithoutSeconds(dir_.Read(Out("a") + "/fitness.csv"));
  EXPECT_EQ(resumed_csv.size(), 4u);
  EXPECT_EQ(resumed_csv, WithoutSeconds(dir_.Read(Out("b") + "/fitness.csv")));
  EXPECT_EQ(dir_.Read(Out("a") + "/best_genome.json"), dir_.Read(Out("b") + "/best_genome.json"));
  EXPECT_EQ(Checkpoint(Out("a"))["champion"], Checkpoint(Out("b"))["champion"]);
  // (Not pagmo_state as text: pagmo 2.18's CMA-ES saves a vector it never initialises or uses, whose bytes vary.)
}

// Issue 21: Ctrl-C in the middle of a run, then `--resume DIR` and nothing else: the run continues with every
// setting it was started with — scenario, population (not the scenario's), seed, and its 4 generations (not the
// scenario's 2) — and ends where an uninterrupted run ends, bit for bit.
TEST_F(OrcsEvolveTest, AnInterruptedRunResumedWithOnlyResumeKeepsItsSettingsAndEqualsAnUninterruptedOne) {
  const std::string scenario = Scenario(2.0);
  const std::vector<std::string> settings = {"--generations", "4", "--population", "6", "--seed", "7",
                                             "--validate", "0"};
  std::vector<std::string> cut = {kBin + "orcs-batch", "evolve", scenario, "--workers", "2", "--no-plot",
                                  "--out", Out("cut")};
  cut.insert(cut.end(), settings.begin(), settings.end());
  {
    test_support::BackgroundProcess evolve(cut);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (Lines(ReadIfThere(Out("cut") + "/fitness.csv")).size() < 3 &&
           std::chrono::steady_clock::now() < deadline) {
      if (evolve.Wait(std::chrono::milliseconds(20)).has_value()) break;
    }
    evolve.Signal(SIGINT);
    const std::optional<ProcessResult> ended = evolve.Wait(std::chrono::milliseconds(60000));
    ASSERT_TRUE(ended.has_value());
    ASSERT_EQ(ended->exit_code, 130) << "interrupted before its 4 generations: " << ended->out << ended->err;
    EXPECT_THAT(ended->err, HasSubstr("interrupted (Ctrl-C or SIGTERM) after generation"));
  }
  EXPECT_EQ(nlohmann::json::parse(dir_.Read(Out("cut") + "/progress.json"))["state"], "interrupted");
  const std::size_t done = Lines(dir_.Read(Out("cut") + "/fitness.csv")).size();
  ASSERT_LT(done, 6u);

  const ProcessResult resumed =
      RunProcess({kBin + "orcs-batch", "evolve", "--resume", Out("cut"), "--workers", "2", "--no-plot"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("resuming after generation " + std::to_string(done - 2)));
  EXPECT_THAT(resumed.err, HasSubstr("6 genomes per generation"));

  std::vector<std::string> whole = {kBin + "orcs-batch", "evolve", scenario, "--workers", "2", "--no-plot",
                                    "--out", Out("whole")};
  whole.insert(whole.end(), settings.begin(), settings.end());
  const ProcessResult uninterrupted = RunProcess(whole);
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;
  const std::vector<std::string> resumed_csv = WithoutSeconds(dir_.Read(Out("cut") + "/fitness.csv"));
  EXPECT_EQ(resumed_csv.size(), 6u) << "a header and generations 0 to 4";
  EXPECT_EQ(resumed_csv, WithoutSeconds(dir_.Read(Out("whole") + "/fitness.csv")));
  EXPECT_EQ(dir_.Read(Out("cut") + "/best_genome.json"), dir_.Read(Out("whole") + "/best_genome.json"));

  // A contradiction is refused; the generations may be raised.
  ExpectOneLineBadInput(
      RunProcess({kBin + "orcs-batch", "evolve", "--resume", Out("cut"), "--population", "8", "--workers", "2"}));
}

// A pseudo-terminal's output as a reader would describe it: each state of the redrawn line while it ran, then the
// screen at the end ('\r' returns to the line's start, "\x1b[K" erases the rest of it; the terminal ends lines with
// "\r\n"). `folder`, the test's temporary one, is left out.
std::string TerminalTranscript(std::string text, const std::string& command, const std::string& folder) {
  const auto erase_all = [&text](const std::string& what, const std::string& with) {
    for (std::size_t at; (at = text.find(what)) != std::string::npos;) text.replace(at, what.size(), with);
  };
  erase_all("\x1b[K", "");
  erase_all("\r\n", "\n");
  erase_all(folder + "/", "");
  std::string frames, screen;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> parts;
    std::istringstream pieces(line);
    for (std::string piece; std::getline(pieces, piece, '\r');) {
      if (!piece.empty()) parts.push_back(piece);
    }
    if (parts.empty()) continue;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) frames += "  " + parts[i] + "\n";
    screen += "  " + parts.back() + "\n";
  }
  return "$ " + command + "\n\nwhile a generation runs, its line is redrawn in place:\n" + frames +
         "\nthe screen when it has ended:\n" + screen;
}

// Issue 21: on a terminal (a pseudo-terminal from util-linux's `script`), a generation shows its progress while it
// runs — jobs done of the population and the best and median fitness so far — and then its summary line.
TEST_F(OrcsEvolveTest, OnATerminalEachGenerationShowsItsJobsAndFitnessWhileItRuns) {
  const std::string scenario = Scenario();
  const std::string command = kBin + "orcs-batch evolve " + scenario + " --workers 2 --no-plot --validate 0 --out " +
                              Out("tty") + " --generations 1 --population 5";
  const ProcessResult typed = RunProcess({"/usr/bin/script", "-qec", command, "/dev/null"});
  ASSERT_EQ(typed.exit_code, 0) << typed.out;
  EXPECT_THAT(typed.out, HasSubstr("generation 1/1: 1/5 jobs (ok 1, failed 0)"));  // the first result is drawn
  EXPECT_THAT(typed.out, HasSubstr("in this generation so far"));
  EXPECT_THAT(typed.out, HasSubstr("\r\x1b[Kgeneration 1/1: best "));  // the summary replaces the progress line
  // For docs/evolution.md: what the terminal showed, as text (ORCS_SCREENSHOT_DIR, like the browser tests'
  // screenshots; relative to the repository).
  if (const char* shots = std::getenv("ORCS_SCREENSHOT_DIR")) {
    const fs::path folder = fs::path(shots).is_absolute() ? fs::path(shots) : fs::path(ORCS_SOURCE_DIR) / shots;
    std::string shown = command.substr(command.find("orcs-batch"));  // without the build's and the test's folders
    for (std::size_t at; (at = shown.find(dir_.path().string() + "/")) != std::string::npos;) {
      shown.erase(at, dir_.path().string().size() + 1);
    }
    std::ofstream(folder / "evolve-progress.txt") << TerminalTranscript(typed.out, shown, dir_.path().string());
  }
}

TEST_F(OrcsEvolveTest, BadInputExitsTwoWithOneLineBeforeAnythingRuns) {
  const std::string scenario = Scenario();

  const ProcessResult small = Evolve(scenario, {"--population", "3", "--out", Out("small")});
  ExpectOneLineBadInput(small);
  EXPECT_THAT(small.err, AllOf(HasSubstr("walk.json"), HasSubstr("population 3"), HasSubstr("cmaes needs at least 5")));
  EXPECT_FALSE(fs::exists(Out("small")));

  const ProcessResult unknown = Evolve(scenario, {"--algorithm", "nonsense", "--out", Out("unknown")});
  ExpectOneLineBadInput(unknown);
  EXPECT_THAT(unknown.err, HasSubstr("--algorithm 'nonsense'"));
  EXPECT_FALSE(fs::exists(Out("unknown")));

  fs::create_directories(Out("empty"));
  const ProcessResult no_checkpoint = Evolve(scenario, {"--resume", Out("empty")});
  ExpectOneLineBadInput(no_checkpoint);
  EXPECT_THAT(no_checkpoint.err, AllOf(HasSubstr(Out("empty")), HasSubstr("no checkpoint.json")));
  EXPECT_TRUE(fs::is_empty(Out("empty")));

  const ProcessResult both = Evolve(scenario, {"--resume", Out("x"), "--out", Out("y")});
  ExpectOneLineBadInput(both);
  EXPECT_THAT(both.err, AllOf(HasSubstr("--resume"), HasSubstr("--out")));
  EXPECT_FALSE(fs::exists(Out("x")));
  EXPECT_FALSE(fs::exists(Out("y")));

  // A finished run (generation 0 only, no validation) to refuse.
  const ProcessResult done =
      Evolve(scenario, {"--out", Out("done"), "--generations", "0", "--validate", "0", "--quiet"});
  ASSERT_EQ(done.exit_code, 0) << done.err;
  const std::string checkpoint = dir_.Read(Out("done") + "/checkpoint.json");
  const std::string workers_log = dir_.Read(Out("done") + "/workers.log");
  ASSERT_FALSE(checkpoint.empty());

  const ProcessResult again = Evolve(scenario, {"--out", Out("done")});
  ExpectOneLineBadInput(again);
  EXPECT_THAT(again.err, AllOf(HasSubstr("holds an evolution run already"), HasSubstr("--resume " + Out("done"))));

  // The same scenario name with another duration: its digest differs.
  const std::string longer = dir_.Write("longer/walk.json", WalkScenario(0.6));
  const ProcessResult other = Evolve(longer, {"--resume", Out("done")});
  ExpectOneLineBadInput(other);
  EXPECT_THAT(other.err,
              AllOf(HasSubstr("written for scenario 'tiny-walk'"), HasSubstr("digest"), HasSubstr("longer/walk.json")));

  // pso_gen runs are not resumed (pagmo 2.18 does not save the particles' velocities).
  const ProcessResult swarm = Evolve(scenario, {"--resume", Out("done"), "--algorithm", "pso_gen"});
  ExpectOneLineBadInput(swarm);
  EXPECT_THAT(swarm.err, AllOf(HasSubstr("--resume " + Out("done")), HasSubstr("pso_gen run cannot be resumed")));

  // Nothing ran: the folder is as the finished run left it.
  EXPECT_EQ(dir_.Read(Out("done") + "/checkpoint.json"), checkpoint);
  EXPECT_EQ(dir_.Read(Out("done") + "/workers.log"), workers_log);
}

TEST_F(OrcsEvolveTest, PlotScriptDrawsAPngAndNamesTheLineOfADamagedCsv) {
  if (RunProcess({"/usr/bin/python3", "-c", "import matplotlib"}).exit_code != 0) {
    GTEST_SKIP() << "/usr/bin/python3 has no matplotlib (scripts/setup.sh installs python3-matplotlib)";
  }
  const std::string script = ORCS_SOURCE_DIR "/scripts/plot_evolution.py";
  // As orcs-batch evolve writes it; generation 0 without ok jobs (empty fields).
  dir_.Write("run/fitness.csv",
             "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds\n"
             "0,5,5,,,,,,0.5\n"
             "1,5,1,2.5,1.25,1,0.5,2.5,0.25\n"
             "2,5,0,3.75,2,2.25,-1,3.75,0.125\n");
  const ProcessResult plot = RunProcess({"/usr/bin/python3", script, Out("run")});
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  EXPECT_THAT(dir_.Read(Out("run") + "/fitness.png"), StartsWith("\x89PNG"));

  dir_.Write("bad/fitness.csv",
             "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds\n"
             "0,5,0,1,1,1,1,1,0.5\n"
             "1,5,0,abc,1,1,1,1,0.5\n");
  const ProcessResult bad = RunProcess({"/usr/bin/python3", script, Out("bad")});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, AllOf(HasSubstr("fitness.csv:3"), HasSubstr("column 'best'")));
  EXPECT_FALSE(fs::exists(Out("bad") + "/fitness.png"));
}

}  // namespace
}  // namespace orcs
