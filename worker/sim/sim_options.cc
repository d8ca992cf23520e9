#include "worker/sim/sim_options.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "model/scene/engine_names.h"
#include "net/cli_style.h"

namespace orcs::sim {

namespace {

// What the world is and how it runs: the original's -env/-ival/-val/-play, duration, seed and the log.
void AddWorldOptions(CLI::App& app, SimOptions& o) {
  app.add_option("--env", o.environment, "ORCS XML environment file (-env also accepted)");  // checked as it is read
  app.add_option("--ival", o.initial_value_files, "value file loaded before the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--val", o.value_files, "value file loaded after the world is built (repeatable)")
      ->allow_extra_args(false);
  app.add_flag("--strict", o.strict, "refuse a value file naming a path orcs lacks (default: ignore it with a warning)");
  app.add_option("--duration", o.duration, "simulated seconds")->check(cli::NumberIn(0.0, 1e6));  // as a scenario's duration
  app.add_option("--seed", o.seed, "seed of the run's random streams")->check(cli::Seed());
  app.add_option("--engine", o.engine,
                 "physics engine of the world or of the --scenario job (/Simulation/Engine, over value files and "
                 "the scenario's values)")
      ->transform(CLI::IsMember(scene::EngineNames(), CLI::ignore_case));
  app.add_option("--log", o.log, "regular expression of repository values to log each step (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--out", o.out, "CSV file the logged values are written to");
  app.add_option("--play", o.play,
                 "AGENT RECORD: play a keyframe record into the agent's inputs (repeatable, one per agent; "
                 "-play also accepted)")
      ->allow_extra_args(false);
}

// What the program does with the world: record, open in the GUI, print, describe, evaluate a scenario, serve ODCP.
void AddModeOptions(CLI::App& app, SimOptions& o) {
  app.add_option("--record", o.record,
                 "write the run's recording (docs/recording.md) to this file, for orcs-view; with --scenario, "
                 "parameter set --record-set's run");
  app.add_option("--record-set", o.record_set, "with --scenario --record: the parameter set recorded (default 0)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--gui", o.gui,
               "open the world in orcs-view's live mode (the original's GUI) instead of running headless "
               "(-gui also accepted)");
  // The original's -nogui: a run without a window, which is what orcs-sim does anyway.
  app.add_flag("--nogui", o.nogui, "run headless, as without --gui (the original's -nogui; -nogui also accepted)")
      ->excludes("--gui");
  app.add_option("--print-values", o.print_values, "print matching repository values as path=value and exit");
  app.add_flag("--describe", o.describe, "print the bodies, joints and agents as JSON and exit");
  app.add_option("--export-mjcf", o.export_mjcf,
                 "write the world as the MJCF model the MuJoCo engine compiles (docs/model.md) to this file and "
                 "exit; for raw MuJoCo (simulate, benchmarks)");
  app.add_option("--export-robot", o.export_robot,
                 "write the environment's first robot as a robot file (docs/formats.md, \"Robot files\"), with the "
                 "value files' changes applied, to this file and exit");
  CLI::Option* scenario =
      app.add_option("--scenario", o.scenario, "evaluate one job of this scenario (docs/scenarios.md) with --seed and "
                                               "print its result as one JSON line, as orcs-batch writes it");
  app.add_option("--genome", o.genome, "the job's genome as JSON text or @FILE (default: the scenario's \"genome\")")
      ->needs(scenario);
  app.add_flag("--realtime", o.realtime, "pace the steps to the wall clock (one simulated second per second)");
  CLI::Option* port = app.add_option("--port", o.odcp_port,
                                     "serve ODCP 1.0 for each agent from this base port, skipping 45454, and run "
                                     "until stopped unless --duration is given (-port also accepted; 0 = any free "
                                     "port)")
                          ->check(CLI::Range(0, 65535));
  app.add_option("--bind", o.bind_address, "interface the ODCP servers listen on (default 127.0.0.1; * = every one)")
      ->needs(port);
}

// The combinations CLI11 cannot express.
void CheckCombinations(const CLI::App& app, const SimOptions& o) {
  if (!o.log.empty() && o.out.empty()) throw CLI::ValidationError("--log", "needs --out FILE.csv");
  if (o.log.empty() && !o.out.empty()) throw CLI::ValidationError("--out", "needs at least one --log REGEX");
  const bool world_options = !o.environment.empty() || !o.initial_value_files.empty() || !o.value_files.empty() ||
                             !o.play.empty() || !o.log.empty() || !o.print_values.empty() || o.describe ||
                             !o.export_mjcf.empty() || !o.export_robot.empty() || app.count("--duration") > 0 ||
                             o.realtime || o.odcp_port >= 0;
  const bool run_options = !o.play.empty() || !o.log.empty() || !o.record.empty() || !o.scenario.empty() ||
                           !o.print_values.empty() || o.describe || !o.export_mjcf.empty() ||
                           !o.export_robot.empty() || o.realtime ||
                           app.count("--duration") > 0 || o.odcp_port >= 0;
  if (o.gui && run_options) {
    throw CLI::ValidationError("-gui", "opens the world (-env, -ival, -val, --seed) in orcs-view --live; run, log, "
                                       "play or record without -gui, or use orcs-view --live --port P for another "
                                       "port");
  }
  if (o.gui && !o.engine.empty()) {
    throw CLI::ValidationError("--engine", "not with -gui: set /Simulation/Engine in a value file for the live view "
                                           "(-ival FILE)");
  }
  if (o.odcp_port >= 0 && !o.record.empty() && app.count("--duration") == 0) {
    throw CLI::ValidationError("--record", "needs --duration S with -port: a run until stopped has no end to record "
                                           "up to (a recording is held in memory)");
  }
  if (app.count("--record-set") > 0 && (o.scenario.empty() || o.record.empty())) {
    throw CLI::ValidationError("--record-set", "needs --scenario and --record FILE");
  }
  if (!o.scenario.empty() && world_options) {
    throw CLI::ValidationError("--scenario", "takes only --genome, --seed and --engine: the scenario gives the world, the "
                                             "duration and what to log, and runs as fast as it can");
  }
}

}  // namespace

ParsedOptions ParseSimOptions(int argc, const char* const* argv) {
  ParsedOptions parsed;
  SimOptions& o = parsed.options;
  CLI::App app{"orcs-sim: headless simulation of an ORCS environment", "orcs-sim"};
  AddWorldOptions(app, o);
  AddModeOptions(app, o);
  const auto validate = [&] {
    CheckCombinations(app, o);
    o.duration_given = app.count("--duration") > 0;
  };
  parsed.exit_code = cli::ParseArguments(app, argc, argv, {"env", "ival", "val", "play", "port", "gui", "nogui"}, validate);
  return parsed;
}

}  // namespace orcs::sim
