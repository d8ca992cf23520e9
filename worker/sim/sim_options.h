// The options of orcs-sim, the headless local simulator (docs/orcs-sim.md).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace orcs::sim {

struct SimOptions {
  std::string environment;                       ///< -env FILE: ORCS XML environment ("" = floor only)
  std::vector<std::string> initial_value_files;  ///< -ival FILE...: loaded before the world is built
  std::vector<std::string> value_files;          ///< -val FILE...: loaded after the world is built
  bool strict = false;                           ///< --strict: a value file's path orcs lacks is an error, not a warning
  double duration = 10.0;                        ///< --duration: simulated seconds
  bool duration_given = false;                   ///< --duration was on the command line (else -port runs until stopped)
  std::uint64_t seed = 0;                        ///< --seed: seed of every random stream of the run
  std::string engine;                            ///< --engine: /Simulation/Engine, over value files and scenario ("" = theirs)
  std::vector<std::string> log;                  ///< --log REGEX...: repository values logged each step
  std::string out;                               ///< --out FILE.csv: where the log goes
  /// -play AGENT RECORD...: keyframe records played into agents' inputs, driven by simulated time
  std::vector<std::pair<std::string, std::string>> play;
  std::string record;                            ///< --record FILE: the run's recording ("" = none)
  int record_set = 0;                            ///< --record-set K: the scenario's parameter set recorded
  bool gui = false;                              ///< -gui: orcs-view --live on this world instead of a headless run
  bool nogui = false;                            ///< -nogui: headless, as without -gui (the original's flag)
  std::string print_values;                      ///< --print-values REGEX: print matching values and exit
  bool describe = false;                         ///< --describe: print the world as JSON and exit
  std::string export_mjcf;                       ///< --export-mjcf FILE: write the world's MuJoCo model and exit
  std::string export_robot;                      ///< --export-robot FILE: write the first robot as a robot file and exit
  std::string scenario;                          ///< --scenario FILE.json: evaluate one job and print its result
  std::string genome;                            ///< --genome JSON or @FILE: the job's genome ("" = the scenario's)
  bool realtime = false;                         ///< --realtime: steps paced to the wall clock
  int odcp_port = -1;                            ///< -port BASE: ODCP servers; −1 = none, 0 = any
  std::string bind_address = "127.0.0.1";        ///< --bind: interface the ODCP servers listen on
};

/// Result of parsing the command line.
struct ParsedOptions {
  SimOptions options;
  int exit_code = -1;  ///< >= 0: exit now with this code (help printed, or bad options reported)
};

/// Parses argv; on --help prints the help and asks to exit 0; on bad options prints one line to stderr and
/// asks to exit 2.
ParsedOptions ParseSimOptions(int argc, const char* const* argv);

}  // namespace orcs::sim
