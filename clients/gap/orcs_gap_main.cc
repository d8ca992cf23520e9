// orcs-gap: finds where simulation and measured runs disagree, names the missing physical effect, adds it to the
// model and shows the gap shrink (docs/gap.md).
//
//   orcs-gap --rig RIG --measured FILE... [--holdout FILE...] [--model FILE.val] [--workers N | --broker EP]
//            [--out DIR]
//   orcs-gap synth --rig RIG --motion RECORD... [--effect NAME] [--set PATH=VALUE]... --out DIR
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <optional>

#include "clients/gap/broker_replays.h"
#include "clients/gap/gap_progress.h"
#include "clients/gap/gap_report.h"
#include "clients/gap/synthetic_runs.h"
#include "clients/runtime/interrupt.h"
#include "clients/runtime/job_runner.h"
#include "model/control/keyframe_record.h"
#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/identify/effect_catalogue.h"
#include "model/identify/gap_diagnosis.h"
#include "model/identify/probe_motion.h"
#include "model/scene/engine_names.h"
#include "net/cli_style.h"

namespace orcs::gap {

using namespace identify;  // the analysis this command drives (model/identify/)
namespace {

struct GapOptions {
  RigOptions rig;
  std::string model;                  // value file of the current model
  std::string engine;                 // --engine: /Simulation/Engine of every run ("" = the model's, else ODE)
  std::string agent;                  // synth: the agent ("" = Pendulum / Humanoid)
  // diagnose
  std::vector<std::string> measured;
  std::vector<std::string> holdout;
  std::string mapping;
  int workers = 0;
  std::string broker;
  std::string out = "gap-report";
  int generations = 0;  // 0 = the rig's default (GenerationsByDefault)
  bool race = true;
  bool early_stop = true;
  bool relax_scan = false;
  int islands = 0;
  std::string loss = "squared";
  unsigned seed = 1;
  std::vector<std::string> effects;
  // synth
  std::vector<std::string> motions;
  std::vector<std::string> effect_switches;
  std::vector<std::string> sets;
  std::uint64_t noise_seed = 1;
  double duration = 0.0;
  std::string probe;        // synth --probe: a probe motion (model/identify/probe_motion.h) to make and play
  std::string probe_motor;  // the motor it moves ("" = the rig's first)
  bool accelerometers = false;  // synth: log the accelerometer axes too
};

void AddRigOptions(CLI::App& app, GapOptions& o) {
  app.add_option("--rig", o.rig.kind, "aseries (default) or pendulum")->check(CLI::IsMember({"aseries", "pendulum"}));
  app.add_option("--env", o.rig.environment_file, "aseries: the ORCS XML environment the runs were made in");
  app.add_option("--pole-mass", o.rig.pole_mass, "pendulum: pole mass, kg (default 0.5)");
  app.add_option("--pole-length", o.rig.pole_length, "pendulum: pole length, m (default 0.3)");
  app.add_flag("--start-measured", o.rig.start_measured,
               "start each replay at the run's first measured angles (real logs; orcs-sim logs start at the built "
               "pose)");
  app.add_option("--model", o.model, "value file of the current model (default: the original's)");
  app.add_option("--engine", o.engine, "physics engine of every run (/Simulation/Engine, over the model file)")
      ->transform(CLI::IsMember(scene::EngineNames(), CLI::ignore_case));
}

// The model's values: the --model file, then --engine.
std::vector<ValueAssignment> ReadModel(const GapOptions& o) {
  std::vector<ValueAssignment> model = o.model.empty() ? std::vector<ValueAssignment>{} : ValueFile::Read(o.model);
  if (!o.engine.empty()) model.push_back({"/Simulation/Engine", o.engine, "--engine", 0});
  return model;
}

std::vector<Override> HiddenValues(const GapOptions& o) {
  std::vector<Override> hidden;
  for (const std::string& name : o.effect_switches) {
    if (identify::FindEffect(name) == nullptr) throw InputError("--effect: no effect " + text::Quote(name) + " (docs/gap.md)");
    hidden.emplace_back("/Effects/" + name + "/Enabled", "T");
  }
  for (const std::string& set : o.sets) {
    const std::size_t equals = set.find('=');
    if (equals == std::string::npos || equals == 0) throw InputError("--set: expected PATH=VALUE, found " + text::Quote(set));
    hidden.emplace_back(std::string(text::Trim(set.substr(0, equals))), std::string(text::Trim(set.substr(equals + 1))));
  }
  return hidden;
}

// synth --probe: the probe motion's keyframe record, written to OUT/motions/<probe>.csv (to play on the robot and
// in the synthetic run).
std::string WriteProbeRecord(const Rig& rig, const GapOptions& o) {
  const std::string motor = o.probe_motor.empty() ? rig.motors.front() : o.probe_motor;
  const ProbeMotion probe = FindProbe(rig, motor, o.probe);
  const control::KeyframeRecord record = CommandsAsRecord(ProbeRun(rig, probe, nullptr), rig.motors);
  const std::filesystem::path folder = std::filesystem::path(o.out) / "motions";
  std::filesystem::create_directories(folder);
  const std::string path = (folder / (probe.name + ".csv")).string();
  AtomicFile file(path);
  file.stream() << control::FormatKeyframeRecord(
      record, {"orcs-gap probe motion " + probe.name + " of " + rig.agent + "/" + motor + ": " + probe.description,
               "it shows " + probe.shows,
               "play: orcs-sim -play " + rig.agent + " " + path + " (or on the robot)"});
  file.Commit();
  std::cout << "orcs-gap: wrote " << path << " (" << probe.description << ")\n";
  return path;
}

int Synth(const GapOptions& o) {
  const std::vector<ValueAssignment> model = ReadModel(o);
  const std::string agent = !o.agent.empty() ? o.agent : o.rig.kind == "pendulum" ? "Pendulum" : "Humanoid";
  const Rig rig = MakeRig(o.rig, agent, model);
  SynthOptions synth;
  synth.motions = o.motions;
  if (!o.probe.empty()) synth.motions.push_back(WriteProbeRecord(rig, o));
  synth.hidden = HiddenValues(o);
  synth.seed = o.noise_seed;
  synth.duration = o.duration;
  synth.accelerometers = o.accelerometers;
  synth.out = o.out;
  for (const std::string& file : WriteSyntheticRuns(rig, model, synth)) std::cout << "orcs-gap: wrote " << file << "\n";
  return cli::kExitOk;
}

// The synth command of this diagnosis's rig, for the verdict's advice on a motion that tells two effects apart.
std::string SynthCommand(const GapOptions& o) {
  std::string command = "orcs-gap synth --rig " + o.rig.kind;
  if (o.rig.kind == "pendulum") {
    command += " --pole-mass " + text::FormatDouble(o.rig.pole_mass) + " --pole-length " +
               text::FormatDouble(o.rig.pole_length);
  }
  if (!o.rig.environment_file.empty()) command += " --env " + o.rig.environment_file;
  if (!o.model.empty()) command += " --model " + o.model;
  if (!o.engine.empty()) command += " --engine " + o.engine;
  return command;
}

std::vector<MeasuredRun> ReadRuns(const std::vector<std::string>& files, const ColumnMapping* mapping) {
  std::vector<MeasuredRun> runs;
  for (const std::string& file : files) runs.push_back(ReadMeasuredRun(file, mapping));
  return runs;
}

// --relax-scan's default (docs/gap.md, "How a fit works"): on where replays are short (the pendulum rig), off for
// the A-Series, where the relaxations' replays, which always run to their end, would take its example diagnosis
// past 10 minutes on 2 cores (617 s against 521 s, docs/benchmarks.md).
bool RelaxScanByDefault(const std::string& rig) { return rig == "pendulum"; }

// --generations' default: 40 where replays are short (the pendulum rig), 20 on the A-Series, whose replays cost
// some 30 times more (a diagnosis of its example in 3 minutes on 2 cores, docs/benchmarks.md): the local stages from
// several starts after the swarm (docs/gap.md, "How a fit works") do what its later generations did.
int GenerationsByDefault(const std::string& rig) { return rig == "pendulum" ? 40 : 20; }

// The race judges a candidate after a quarter of its swarm's generations, at least 5 (10 of the default 40).
int RaceAfter(int generations) { return std::max(5, generations / 4); }

// --race's default: on, but off with --islands. The race judges a candidate after 10 generations of its swarm,
// before any island has run, and abandons the very candidates the islands are for (LuGre on the servo model).
bool RaceByDefault(int islands) { return islands == 0; }

int Diagnose(const GapOptions& o) {
  const std::vector<ValueAssignment> model = ReadModel(o);
  std::optional<ColumnMapping> mapping;
  if (!o.mapping.empty()) mapping = ReadColumnMapping(o.mapping);
  CheckDisjoint(o.measured, o.holdout);
  const std::vector<MeasuredRun> fit_data = ReadRuns(o.measured, mapping ? &*mapping : nullptr);
  const std::vector<MeasuredRun> holdout_data = ReadRuns(o.holdout, mapping ? &*mapping : nullptr);
  std::vector<MeasuredRun> all = fit_data;
  all.insert(all.end(), holdout_data.begin(), holdout_data.end());
  CheckRunsAgree(all);
  const Rig rig = MakeRig(o.rig, all.front().agent, model);
  std::vector<ReplayRun> fit;
  std::vector<ReplayRun> holdout;
  for (const MeasuredRun& run : fit_data) fit.push_back(MakeReplayRun(rig, run, model));
  for (const MeasuredRun& run : holdout_data) holdout.push_back(MakeReplayRun(rig, run, model));

  DiagnosisOptions options;
  options.fit.generations = o.generations;
  options.fit.abandon_after = RaceAfter(o.generations);
  if (o.race) options.abandon_share = kRaceAbandonShare;
  options.fit.stop_replays_early = o.early_stop;
  options.relax_scan = o.relax_scan;
  options.fit.islands = o.islands;
  options.loss = o.loss == "absolute" ? Loss::kAbsolute : Loss::kSquared;
  options.fit.seed = o.seed;
  options.candidates = o.effects;
  options.synth_command = SynthCommand(o);
  std::filesystem::create_directories(o.out);
  runtime::RunnerOptions runner_options;
  runner_options.broker = o.broker;
  runner_options.workers = o.workers;
  runner_options.log_path = (std::filesystem::path(o.out) / "workers.log").string();
  // Ctrl-C (clients/runtime/interrupt.h): every fit's wait stops within 200 ms and the diagnosis is abandoned. It
  // has no resume: it starts over.
  runner_options.stop = &runtime::InterruptFlag();
  runtime::SetInterruptHint("orcs-gap: stopped at once (a second Ctrl-C); a diagnosis has no resume: run the same "
                          "command again");
  runtime::CatchInterrupts();
  runtime::JobRunner runner(runner_options);
  std::cerr << "orcs-gap: " << fit.size() << " fit run(s), " << holdout.size() << " held-out run(s); "
            << (o.broker.empty() ? std::to_string(runner.local_workers()) + " local workers" : "broker " + o.broker)
            << "\n";
  BrokerReplays replays(runner);
  std::optional<Diagnosis> result;
  runtime::ProgressFile file(o.out, "gap");
  {
    GapProgress progress(std::cerr, [&runner] { return runner.jobs_run(); }, std::chrono::seconds(10), &file,
                         options.loss == Loss::kAbsolute ? "deg" : "deg²");
    options.on_fit = [&progress](const std::string& fitted, const identify::ModelScore* score) {
      progress.OnFit(fitted, score);
    };
    try {
      result = Diagnose(replays, rig, fit, holdout, model, options);
    } catch (const runtime::Interrupted&) {
      file.Finish("interrupted");
      std::cerr << "orcs-gap: interrupted (Ctrl-C or SIGTERM): the diagnosis is abandoned and no report is written "
                   "to " << o.out << "; orcs-gap has no resume: run the same command again\n";
      return runtime::kExitInterrupted;
    }
  }
  const Diagnosis& diagnosis = *result;
  std::vector<ReplayRun> runs = fit;
  runs.insert(runs.end(), holdout.begin(), holdout.end());
  WriteReplays(o.out, diagnosis, rig, model, runs);
  WriteReport(o.out, diagnosis, rig, model, options);
  file.Finish("finished");
  std::cout << diagnosis.verdict << "\n"
            << "orcs-gap: report in " << o.out << "/report.md, fitted model in " << o.out
            << "/model.val; plot with scripts/plot_gap.py " << o.out << "; watch the replays with orcs-view "
            << o.out << "\n";
  return cli::kExitOk;
}

}  // namespace
}  // namespace orcs::gap

int main(int argc, char** argv) {
  using namespace orcs::gap;
  GapOptions o;
  CLI::App app{"orcs-gap: finds where simulation and measured runs disagree and which effect the model lacks",
               "orcs-gap"};
  AddRigOptions(app, o);
  app.add_option("--measured", o.measured, "measured runs (orcs-sim logs, BAM's JSON logs, or any CSV with --mapping)");
  app.add_option("--holdout", o.holdout, "held-out runs, scored but never fitted (default: the last measured run)");
  app.add_option("--mapping", o.mapping, "column mapping JSON for CSVs that are not orcs logs (docs/gap.md)");
  CLI::Option* workers = app.add_option("--workers", o.workers, "local worker processes (default: one per core)")
                             ->check(CLI::Range(1, 4096));
  app.add_option("--broker", o.broker, "a running broker's client endpoint instead of local workers")
      ->check(orcs::cli::Endpoint())
      ->excludes(workers);
  app.add_option("--out", o.out, "output folder (default gap-report)");
  app.add_option("--generations", o.generations,
                 "swarm generations per fit (default 40 on the pendulum rig, 20 on the A-Series); the race judges "
                 "after a quarter of them (at least 5)")
      ->check(CLI::Range(1, 10000));
  CLI::Option* race = app.add_flag("--race,!--no-race", o.race,
               "race the candidates (default, but off with --islands): after a quarter of its generations each "
               "candidate's best point is polished and scored on the held-out runs; one far behind the best candidate "
               "or no better than nothing missing is abandoned, once its fit has converged; --no-race fits every "
               "candidate to the end (docs/gap.md)");
  app.add_flag("--early-stop,!--no-early-stop", o.early_stop,
               "stop a search's replays once their point cannot beat the best it is compared with (default; the same "
               "fits, sooner); --no-early-stop runs every replay to its end (docs/gap.md)");
  CLI::Option* relax_scan = app.add_flag("--relax-scan,!--no-relax-scan", o.relax_scan,
               "before each effect's fit, let the scan's best point and its neighbours relax the other parameters, "
               "so that a basin the scan misjudges is found (a wide backlash); up to three short polishes more per "
               "candidate. Default: on for the pendulum rig, off for the A-Series, whose replays would take its "
               "diagnosis past 10 minutes on 2 cores (docs/gap.md)");
  app.add_option("--islands", o.islands,
                 "after each fit's swarm, this many CMA-ES runs side by side from its last generation (default 0: "
                 "none); their best point is a second start for the local search. Finds minima in narrow diagonal "
                 "valleys (LuGre friction on the servo model); turns the race off unless --race is given, since the "
                 "race judges before any island runs; each island costs about 2,400 replays per fit (docs/gap.md)")
      ->check(CLI::Range(0, 64));
  app.add_option("--loss", o.loss,
                 "what the fits minimise and the held-out scores measure: squared (default; the mean squared angle "
                 "error) or absolute (the mean absolute error, BAM's: less pulled by a few large errors such as a "
                 "stuck segment). An effect is named when its score is below half the refit's in that measure "
                 "(docs/gap.md)")
      ->check(CLI::IsMember({"squared", "absolute"}));
  app.add_option("--seed", o.seed, "seed of the fits (default 1)")->check(orcs::cli::Seed(UINT32_MAX));
  app.add_option("--effects", o.effects, "only these candidate effects (default: the whole catalogue)")->delimiter(',');
  CLI::App* synth = app.add_subcommand("synth", "make \"measured\" runs with hidden values (an effect, mistuned gains)");
  AddRigOptions(*synth, o);
  synth->add_option("--motion", o.motions, "keyframe records to play, one run each");
  synth->add_option("--effect", o.effect_switches, "switch an effect on (repeatable)");
  synth->add_option("--set", o.sets, "PATH=VALUE, a hidden value (repeatable)");
  synth->add_option("--seed", o.noise_seed, "noise seed of the first run (default 1)")->check(orcs::cli::Seed());
  synth->add_option("--duration", o.duration, "seconds per run (default: the record's length)");
  synth->add_option("--agent", o.agent, "the agent (default Pendulum / Humanoid)");
  synth->add_option("--probe", o.probe,
                    "also make and play a probe motion that tells effects apart (slow_reversals, speed_ladder, "
                    "loaded_lowering, fast_steps, small_steps, limp_drops, torque_ladder; docs/gap.md): its keyframe "
                    "record goes to OUT/motions/NAME.csv, its run to OUT/NAME.csv");
  synth->add_option("--probe-motor", o.probe_motor, "the motor the probe moves (default: the rig's first)");
  synth->add_flag("--accelerometers", o.accelerometers,
                  "log the agent's accelerometer axes too (A-Series: the eight ADXL213 boards), with the noise of "
                  "/AccelSensor/Deviation; orcs-gap compares them beside the joint angles (docs/gap_measured_data.md)");
  synth->add_option("--out", o.out, "output folder")->required();
  const int parsed = orcs::cli::ParseArguments(app, argc, argv, {"env"}, [&] {
    if (!synth->parsed() && o.measured.empty()) throw CLI::RequiredError("--measured");
    if (synth->parsed() && o.motions.empty() && o.probe.empty()) {
      throw CLI::ValidationError("synth: give --motion RECORD... or --probe NAME (or both)");
    }
  });
  if (parsed >= 0) return parsed;
  if (relax_scan->count() == 0) o.relax_scan = RelaxScanByDefault(o.rig.kind);
  if (o.generations == 0) o.generations = GenerationsByDefault(o.rig.kind);
  if (race->count() == 0 && o.race != RaceByDefault(o.islands)) {
    o.race = RaceByDefault(o.islands);
    std::cerr << "orcs-gap: --islands turns the race off (it would judge the candidates before any island runs); "
                 "--race keeps it\n";
  }
  return orcs::cli::RunProgram("orcs-gap", [&] { return synth->parsed() ? Synth(o) : Diagnose(o); });
}
