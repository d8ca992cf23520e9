// orcs-robot: plays a controller on the physical robot through its Dynamixel bus, safety first, and logs the run
// as a measured run for orcs-gap (docs/hardware.md).
//
//   orcs-robot --map scenarios/robots/aseries.joints.json --port /dev/ttyUSB0 --play scenarios/motions/waist_bend.csv
//              --out run.csv [--rate 50] [--yes] [--dry-run]
#include <CLI/CLI.hpp>

#include <csignal>
#include <filesystem>
#include <iostream>

#include "base/run_program.h"
#include "hardware/emulator/servo_bus_emulator.h"
#include "hardware/robot/odcp_source.h"
#include "hardware/robot/robot_run_folder.h"
#include "hardware/robot/robot_session.h"
#include "hardware/robot/simulated_shafts.h"
#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::hardware {
namespace {

using cli::kExitBadInput;   // a bad map, record or option: one line names it
using cli::kExitOk;
using cli::kExitRunFailed;  // the bus or a servo stopped the run (torque off)
constexpr int kExitInterrupted = 130;  // Ctrl-C (torque off)
constexpr double kOdcpSessionSeconds = 600.0;  // an ODCP session's bound without --duration (its log is in memory)

std::atomic<bool> g_interrupted{false};  // set by SIGINT/SIGTERM, read by the control loop every period

extern "C" void OnInterrupt(int) { g_interrupted = true; }

void InstallInterruptHandler() {
  struct sigaction action = {};
  action.sa_handler = OnInterrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

struct Options {
  std::string map;          // joint map file
  std::string port;         // serial port of the bus
  std::string play;         // keyframe record to play
  std::string scenario;     // or a scenario's controller to run
  std::string genome;       // its genome (JSON; default: the scenario's)
  int odcp_port = -1;       // serve ODCP 1.0 here for a motion editor (0 = any; -1 = no)
  std::string odcp_bind = "127.0.0.1";  // the ODCP socket's interface
  double duration = 0.0;    // s of a controller's run (0: the scenario's) or of an ODCP session (0: 600)
  int timeout_ms = 0;       // wait for a servo's answer (0: 20 ms on a port, 250 ms on the emulator)
  std::string out;          // the run's log (a measured run)
  double rate_hz = 50.0;    // control rate
  int deadline_streak = 5;  // overruns in a row that stop the run
  bool dry_run = false;     // print what would be sent, send nothing
  bool yes = false;         // skip the first pose's confirmation
  bool emulate = false;     // play on the servo-bus emulator instead of a port
  std::string emulate_env;  // --emulate: orcs's simulation in this environment turns the shafts
  std::vector<std::string> emulate_values;  // value files of that simulation (hidden effects)
  bool unpaced = false;     // --emulate with a simulation: no waiting between periods
  std::string bam_out;      // the run in BAM's JSON log format (one-joint maps)
  BamRig bam;               // what that log says of the rig
  std::string twin_out;     // the simulated twin's log (runs the twin)
  std::string twin_env;     // the twin's environment ("" = the default world)
  std::string view;         // a folder orcs-view follows while the robot moves (runs the twin)
};

// Shows where the robot is and where the first pose takes it; true when the user agrees (or passed --yes).
bool ConfirmFirstPose(RobotSession& session, CommandSource& source, bool yes) {
  const std::vector<double> now = session.ReadAngles();
  const std::vector<double> pose = session.FirstPose(source, now);
  double largest = 0.0;
  std::size_t which = 0;
  for (std::size_t j = 0; j < pose.size(); ++j) {
    if (std::abs(pose[j] - now[j]) > largest) largest = std::abs(pose[j] - now[j]), which = j;
  }
  std::cerr << "orcs-robot: the first pose moves " << session.map().joints.size() << " joints, the most "
            << session.map().joints[which].joint << " by " << text::FormatDouble(std::round(largest * 10) / 10)
            << "° (from " << text::FormatDouble(std::round(now[which] * 10) / 10) << "° to "
            << text::FormatDouble(std::round(pose[which] * 10) / 10) << "°)\n";
  if (yes) return true;
  std::cerr << "orcs-robot: torque on and move there? Keep a hand near the power switch. [y/N] " << std::flush;
  std::string answer;
  if (!std::getline(std::cin, answer)) return false;
  return answer == "y" || answer == "Y" || answer == "yes";
}

int Run(const Options& o) {
  JointMap map = ReadJointMap(o.map);
  if (!o.bam_out.empty() && map.joints.size() != 1) {  // said before anything moves, not after the run
    throw InputError(o.map, 0, "--bam-out: BAM's log format holds one servo; this map has " +
                                   std::to_string(map.joints.size()) + " joints (use --out for the robot's log)");
  }
  std::unique_ptr<RecordSource> record;
  if (!o.play.empty()) {
    record = std::make_unique<RecordSource>(control::ReadKeyframeRecord(o.play, static_cast<int>(map.joints.size())));
  }
  std::unique_ptr<ServoBusEmulator> emulator;  // --emulate: the map's servos on a pseudo-terminal of our own
  std::string port = o.port;
  if (o.emulate) {
    EmulatorOptions emulated;
    emulated.table = map.servo;
    for (const JointMapping& joint : map.joints) emulated.ids.push_back(joint.id);
    if (!o.emulate_env.empty() || !o.emulate_values.empty()) {
      emulated.shafts = std::make_shared<SimulatedShafts>(o.emulate_env, map, o.emulate_values);
      emulated.period_s = 1.0 / o.rate_hz;
    }
    emulator = std::make_unique<ServoBusEmulator>(emulated);
    port = emulator->port();
  }
  std::unique_ptr<dynamixel::DynamixelBus> bus;
  if (!o.dry_run) {
    dynamixel::BusOptions bus_options;
    bus_options.protocol = map.servo.protocol;
    // The emulator shares this machine's cores with everything else on it, so it may answer late.
    bus_options.timeout = std::chrono::milliseconds(o.timeout_ms > 0 ? o.timeout_ms : o.emulate ? 250 : 20);
    bus = std::make_unique<dynamixel::DynamixelBus>(OpenSerialLink(port, map.baud), bus_options);
  }
  // The twin runs for --twin-out, and for a controller, whose values it holds.
  std::unique_ptr<SimulatedTwin> twin;
  if (!o.twin_out.empty() || !o.scenario.empty() || !o.view.empty()) {
    twin = std::make_unique<SimulatedTwin>(o.twin_env, map);
  }
  std::unique_ptr<ControllerSource> controller;
  if (!o.scenario.empty()) {
    std::optional<nlohmann::json> genome;
    if (!o.genome.empty()) genome = ParseJson(ReadTextFile(o.genome), o.genome);
    controller = std::make_unique<ControllerSource>(o.scenario, genome ? &*genome : nullptr, o.duration, *twin, map);
  }
  std::unique_ptr<OdcpSource> editor;
  if (o.odcp_port >= 0) {
    osp::OdcpServerOptions server;
    server.bind_address = o.odcp_bind;
    server.port = static_cast<std::uint16_t>(o.odcp_port);
    server.name = "orcs-robot odcp";
    editor = std::make_unique<OdcpSource>(map, server, o.duration > 0 ? o.duration : kOdcpSessionSeconds);
  }
  CommandSource& source = record       ? static_cast<CommandSource&>(*record)
                          : editor     ? static_cast<CommandSource&>(*editor)
                                       : static_cast<CommandSource&>(*controller);
  const std::string played = record   ? o.play
                             : editor ? "the ODCP editor's commands"
                                      : o.scenario + (o.genome.empty() ? "" : " with " + o.genome);
  std::unique_ptr<RobotRunFolder> view;  // made now: a folder that cannot be written is said before anything moves
  if (!o.view.empty()) {
    nlohmann::json about = {{"map", o.map},
                            {"played", played},
                            {"port", o.dry_run ? "dry run" : o.emulate ? "emulated" : o.port},
                            {"servo", map.servo.name},
                            {"rate_hz", o.rate_hz}};
    if (std::isfinite(source.duration())) about["duration_s"] = source.duration();
    view = std::make_unique<RobotRunFolder>(o.view, map, o.twin_env, about);
  }
  SessionOptions session_options;
  session_options.twin = twin.get();
  if (view) session_options.on_row = [&](const RobotRow& row) { view->Add(row, twin.get()); };
  session_options.paced = !o.unpaced;
  session_options.rate_hz = o.rate_hz;
  session_options.deadline_streak = o.deadline_streak;
  session_options.dry_run = o.dry_run ? &std::cout : nullptr;
  RobotSession session(std::move(map), std::move(bus), session_options);
  session.CheckServos();
  if (!o.dry_run && !ConfirmFirstPose(session, source, o.yes)) {
    std::cerr << "orcs-robot: not confirmed: nothing was sent (pass --yes to skip the question)\n";
    return kExitBadInput;
  }
  std::cerr << "orcs-robot: playing " << played << " on " << session.map().joints.size() << " "
            << session.map().servo.name << (o.dry_run ? " (dry run: nothing is sent)" : "") << " at "
            << text::FormatDouble(o.rate_hz) << " Hz; Ctrl-C turns the torque off\n";
  if (editor) {  // said once torque is about to come on: an editor's commands act from here on
    std::cout << "orcs-robot odcp=" << editor->endpoint().ToString() << std::endl;
  }
  const RobotRun run = session.Play(source, g_interrupted);
  if (view) view->Finish(run);
  if (!o.out.empty()) {
    AtomicFile file(o.out);
    file.stream() << FormatRobotLog(session.map(), run,
                                    {"map: " + o.map, "played: " + played, "port: " + (o.dry_run ? "dry run" : o.emulate ? "emulated" : o.port),
                                     "rate_hz: " + text::FormatDouble(o.rate_hz),
                                     "stop: " + StopReasonName(run.reason)});
    file.Commit();
  }
  if (!o.bam_out.empty()) {
    BamRig rig = o.bam;
    if (rig.trajectory.empty()) rig.trajectory = editor ? "odcp" : std::filesystem::path(record ? o.play : o.scenario).stem().string();
    AtomicFile file(o.bam_out);
    file.stream() << FormatBamLog(session.map(), run, rig);
    file.Commit();
  }
  if (twin && !o.twin_out.empty()) {
    AtomicFile file(o.twin_out);
    file.stream() << FormatRobotLog(session.map(), run,
                                    {"map: " + o.map, "played: " + played,
                                     "environment: " + (o.twin_env.empty() ? "the default world" : o.twin_env),
                                     "rate_hz: " + text::FormatDouble(o.rate_hz),
                                     "twin: " + (run.twin_status.empty() ? "ran to the end" : run.twin_status)},
                                    LogSide::kTwin);
    file.Commit();
  }
  if (twin && !run.twin_status.empty()) std::cerr << "orcs-robot: " << run.twin_status << "\n";
  const std::string ended = editor && editor->finished() ? "the editor disconnected" : "finished";
  std::cerr << "orcs-robot: " << (run.reason == StopReason::kFinished ? ended : "stopped: " + run.message)
            << "; torque off; " << run.rows.size() << " periods, " << run.clamped << " commands clamped to the limits, "
            << run.missed_deadlines << " deadlines missed";
  if (const auto* b = session.bus()) {
    std::cerr << "; bus: " << b->counts().instructions << " instructions, " << b->counts().timeouts << " timeouts, "
              << b->counts().checksum_errors << " checksum errors, " << b->counts().retries << " retries";
  }
  std::cerr << (o.out.empty() ? "" : "; log " + o.out) << (o.twin_out.empty() ? "" : "; twin " + o.twin_out)
            << (o.view.empty() ? "" : "; orcs-view " + o.view) << "\n";
  switch (run.reason) {
    case StopReason::kFinished: return kExitOk;
    case StopReason::kInterrupted: return kExitInterrupted;
    default: return kExitRunFailed;
  }
}

}  // namespace
}  // namespace orcs::hardware

int main(int argc, char** argv) {
  using orcs::hardware::Options;
  Options o;
  CLI::App app{"orcs-robot: plays a keyframe record, a controller or a motion editor's ODCP commands on the physical\n"
               "robot through its Dynamixel bus, joint limits enforced, torque off on Ctrl-C, a bus error, a servo alarm or\n"
               "missed deadlines; logs the run as a measured run for orcs-gap (docs/hardware.md)"};
  app.add_option("--map", o.map, "joint map (JSON): joint ↔ servo id, direction, offset, limits (scenarios/robots/)")
      ->required();
  app.add_option("--port", o.port, "the bus's serial port (/dev/ttyUSB0); not with --dry-run");
  auto* play = app.add_option("--play", o.play, "keyframe record to play (raw layout, the map's joints in order)");
  auto* scenario = app.add_option("--scenario", o.scenario, "or run this scenario's controller (a network genome from "
                                  "evolve, an oscillator, a script) on the robot; its values are the twin's, its joint "
                                  "sensors the robot's");
  auto* odcp = app.add_option("--odcp", o.odcp_port, "or serve ODCP 1.0 on this UDP port (0 = any) and play what a "
                               "motion editor sends (MotionEditor, a slider tool) until it disconnects")
                   ->check(CLI::Range(0, 65535));
  play->excludes(scenario);
  odcp->excludes(play)->excludes(scenario);
  app.add_option("--odcp-bind", o.odcp_bind, "with --odcp: the interface to listen on (default 127.0.0.1)")
      ->needs(odcp);
  app.add_option("--genome", o.genome, "with --scenario: the genome (JSON, e.g. evolve's best_genome.json)")
      ->needs(scenario);
  app.add_option("--duration", o.duration, "with --scenario: seconds to run (default: the scenario's); with --odcp: "
                 "the session's longest (default 600)")
      ->check(CLI::PositiveNumber);
  app.add_option("--out", o.out, "write the run's log here (a measured run orcs-gap reads)");
  app.add_option("--rate", o.rate_hz, "control rate, Hz (default 50)")->check(CLI::Range(1.0, 1000.0));
  app.add_option("--deadline-streak", o.deadline_streak, "overrun periods in a row that stop the run (default 5)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--emulate-env", o.emulate_env, "with --emulate: orcs's simulation of this environment turns the "
                 "emulated shafts, one control period per goal write (default: kinematic shafts)")
      ->check(CLI::ExistingFile);
  app.add_option("--emulate-val", o.emulate_values, "with --emulate: value files of that simulation (the servo "
                 "model, hidden effects such as /Effects/TransportDelay/...); repeatable")
      ->check(CLI::ExistingFile);
  app.add_flag("--unpaced", o.unpaced, "with --emulate-env/--emulate-val: run the periods back to back (the emulated "
               "world advances per command, so only the wall time changes)");
  app.add_option("--bam-out", o.bam_out, "also write the run as BAM's JSON log (one-joint maps; docs/hardware.md)");
  app.add_option("--bam-mass", o.bam.mass, "BAM log: the load's mass, kg");
  app.add_option("--bam-length", o.bam.length, "BAM log: the load's distance from the axis, m");
  app.add_option("--bam-kp", o.bam.kp, "BAM log: the servo's firmware P gain during the run");
  app.add_option("--twin-out", o.twin_out, "run the simulated twin on the same commands, period by period, and write "
                 "its log here (the robot's rows, the twin's angles)");
  app.add_option("--view", o.view, "keep a folder orcs-view follows while the robot moves: the robot posed by its "
                 "measured angles and its simulated twin, recorded period by period (runs the twin)");
  app.add_option("--twin-env", o.twin_env, "the twin's environment (XML; default: the A-Series on the floor)")
      ->check(CLI::ExistingFile);
  app.add_option("--timeout-ms", o.timeout_ms, "wait this long for a servo's answer before asking again (default 20 "
                 "on a port, 250 with --emulate)")->check(CLI::Range(1, 10000));
  app.add_flag("--dry-run", o.dry_run, "print every packet that would be sent; open no port");
  app.add_flag("--yes", o.yes, "do not ask before moving to the first pose");
  app.add_flag("--emulate", o.emulate, "play on emulated servos (the servo-bus emulator on a pseudo-terminal): try a "
               "record, measure the loop, with no robot");
  try {
    app.parse(argc, argv);
    if (o.port.empty() && !o.dry_run && !o.emulate) throw CLI::RequiredError("--port (or --emulate, --dry-run)");
    if (o.play.empty() && o.scenario.empty() && o.odcp_port < 0) {
      throw CLI::RequiredError("--play, --scenario or --odcp");
    }
    if (o.duration > 0 && o.scenario.empty() && o.odcp_port < 0) {
      throw CLI::ValidationError("--duration", "only with --scenario or --odcp: a record lasts as long as its rows");
    }
    const bool simulated = !o.emulate_env.empty() || !o.emulate_values.empty();
    if (simulated && !o.emulate) throw CLI::ValidationError("--emulate-env/--emulate-val", "need --emulate");
    if (o.unpaced && !simulated) {
      throw CLI::ValidationError("--unpaced", "only with --emulate-env or --emulate-val: a real robot and the "
                                              "kinematic emulator keep the wall clock");
    }
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "orcs-robot: " << e.what() << " (see orcs-robot --help)\n";
    return orcs::hardware::kExitBadInput;
  }
  orcs::hardware::InstallInterruptHandler();
  return orcs::cli::RunProgram("orcs-robot", [&] {
    try {
      return orcs::hardware::Run(o);
    } catch (const orcs::dynamixel::BusError& error) {  // before the run: the torque was never turned on
      std::cerr << "orcs-robot: stopped before the run: " << error.what() << "; the torque was not turned on\n";
      return orcs::hardware::kExitRunFailed;
    }
  });
}
