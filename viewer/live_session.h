// orcs-view's live mode: one simulation running in the server (the original's GUI, docs/viewer.md). A thread steps
// it — in real time or as fast as it can — and publishes frames; pages read frames, and the one page holding the
// control token runs, pauses, steps and resets it, sets values (motor sliders, the property editor), saves and
// loads value files and starts the Logger. With --osp (orcs-osp -gui) OSP clients step and reset it instead:
// orcs-osp's gateway runs in the stepping thread and the pages' commands run between its datagrams. Every public
// method is safe to call from any server thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <stop_token>
#include <thread>
#include <vector>

#include "model/core/value_logger.h"
#include "model/evaluation/recording_layout.h"
#include "model/scene/simulation.h"
#include "worker/osp/episode_recorder.h"
#include "worker/osp/osp_gateway.h"

namespace orcs::viewer {

/// --osp (orcs-osp -gui): OSP clients drive the live simulation — they step and reset it — while pages watch, set
/// values and log, as the original ClientSimulator did with its -gui. The page's Run, Pause, Step and Reset are
/// refused then. The gateway is orcs-osp's (worker/osp/osp_gateway.h), with its ODCP servers.
struct LiveOspOptions {
  bool enabled = false;                    ///< --osp
  int port = -1;                           ///< --osp-port; -1 = /UDPCommunication/ServerPort (45454); 0 = any
  int odcp_port = -1;                      ///< --odcp-port; -1 = /SimpleUdpMotorInterface/ServerPort; 0 = any
  std::string bind_address = "127.0.0.1";  ///< --osp-bind: the OSP and ODCP sockets' interface
  double client_timeout_seconds = 10.0;    ///< --client-timeout, s
  std::string record;                      ///< --record DIR: one recording per episode (osp/episode_recorder.h)
};

struct LiveOptions {
  std::string environment;                       ///< ORCS XML environment, "" = one A-Series on the floor
  std::vector<std::string> initial_value_files;  ///< -ival: before the build
  std::vector<std::string> value_files;          ///< -val: after the build
  bool strict = false;                           ///< --strict: a value file's path orcs lacks is an error
  std::uint64_t seed = 0;                        ///< /Simulation/Seed of every reset
  std::string files_dir = "orcs-view-files";     ///< where save/load/logger files live
  bool start_running = false;                    ///< run at start instead of paused
  std::size_t log_max_bytes = std::size_t{64} << 20;  ///< --log-max-mib: a log stops at this size
  double log_max_seconds = 600.0;                ///< --log-max-seconds: a log stops after this long (wall clock)
  double control_timeout = 10.0;                 ///< --control-timeout: a silent controller loses control (s)
  LiveOspOptions osp;                            ///< --osp: OSP clients step it instead
};

/// One published state of the simulation.
struct LiveFrame {
  std::int64_t step = 0;                           ///< steps since the last reset
  std::int64_t serial = 0;                         ///< increases with every published frame, across resets
  double time = 0.0;                               ///< simulated s
  std::vector<float> values;                       ///< every channel of world()
  std::vector<evaluation::ContactSample> contacts;  ///< of the last step
  /// Which world() the values belong to: it grows when a reset compiled the world anew (a structure value changed,
  /// a box's size or a robot's mass): the page fetches world() again then.
  int world_revision = 0;
};

class LiveSession {
 public:
  /// Builds the world (throws InputError naming the file) and starts the stepping thread, paused.
  explicit LiveSession(const LiveOptions& options);
  /// With --osp: where OSP and ODCP clients find the gateway, one line each ("orcs-view osp=ADDRESS:PORT", then
  /// "orcs-view odcp AGENT=ADDRESS:PORT"); empty without.
  std::vector<std::string> OspEndpointLines() const;
  /// What the page's header names: "live: example.xml" (or "live: one A-Series"), "· driven over OSP" with --osp.
  std::string Title() const;
  ~LiveSession();
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  /// The recording header of the live world (docs/recording.md), as of the newest frame's world_revision.
  nlohmann::json world();

  /// The newest frame after `serial` — waiting up to `wait` for one — or the newest there is.
  LiveFrame FrameAfter(std::int64_t serial, std::chrono::milliseconds wait);
  /// {"running", "realtime", "time", "step", "status", "message", "logging", "logger"}: "logging" is the file
  /// being written or null; "logger" holds {"file", "bytes", "seconds", "max_bytes", "max_seconds", "stopped"}
  /// ("stopped": why the last log ended on its own — a bound reached, control lapsed — or "").
  nlohmann::json State();

  /// A new control token when nobody holds control or the holder was silent for control_timeout (10 s);
  /// "" otherwise.
  std::string Claim();
  /// Whether `token` holds control now; refreshes the holder's silence clock.
  bool Controls(const std::string& token);

  /// "run", "pause", "step" or "reset"; `realtime` paces running to the wall clock; "step" does `steps` steps
  /// (1…kMaxStepsAtOnce), as fast as it can, then pauses. Throws InputError for an unknown action, and for any
  /// action when OSP clients drive the simulation (--osp).
  void Control(const std::string& action, bool realtime, int steps = 1);
  static constexpr int kMaxStepsAtOnce = 100000;
  /// Values whose path matches `pattern` (RE2, bounded): [{"id", "path", "type", "value"}], at most `limit`.
  nlohmann::json Values(const std::string& pattern, std::size_t limit);
  /// Sets a value from text; returns its new text. Throws InputError naming the path and what was expected, and
  /// for a text with a control character (a line feed, a NUL: text::FindControlCharacter) — a value is one line.
  std::string SetValue(const std::string& path, const std::string& text);
  /// Object Properties' "set as initial": object `name`'s pose now is its start pose from the next reset on
  /// (Simulation::KeepPoseAsStart). Throws InputError when `name` is no object of the environment.
  void KeepPoseAsStart(const std::string& name);
  /// Saves the values matching `pattern` as a value file in the files folder. Throws InputError for a bad name.
  void Save(const std::string& file, const std::string& pattern);
  /// Applies a value file from the files folder.
  void Load(const std::string& file);
  /// Value files and logs in the files folder.
  nlohmann::json Files();
  /// Starts writing the values matching `pattern` to a CSV file in the files folder each step; stops the last.
  /// The log ends by itself at log_max_bytes or log_max_seconds, or when control lapses (the page that started
  /// it is silent for control_timeout, or another page takes control); State()'s "logger" says why.
  void StartLogger(const std::string& pattern, const std::string& file);
  void StopLogger();

 private:
  /// Runs `task` on the stepping thread between steps and returns its result (or rethrows its exception): only
  /// that thread touches the simulation, and a request never waits for more than one slice of steps.
  template <typename Task>
  auto OnSimulationThread(Task task) -> decltype(task());
  void Loop(std::stop_token stop);
  // --osp: the gateway's thread runs instead of Loop(); these are its hooks.
  void StartOsp();
  void OnOspCommands();
  void OnOspStep();
  void OnOspReset();
  void RunCommands(std::unique_lock<std::mutex>& lock);
  void StepOnce();
  void Publish();
  std::string FilePath(const std::string& file, const char* extension) const;
  /// Ends the log when it reached a bound or its page lost control (the stepping thread, without command_mutex_).
  void CheckLogger();
  void LayOut();
  void EndLogger(const std::string& why);
  /// Whether `token` holds control now, without refreshing its silence clock.
  bool HeldBy(const std::string& token);

  LiveOptions options_;
  // Owned by the stepping thread (and the constructor, before it starts).
  scene::Simulation simulation_;
  std::unique_ptr<evaluation::RecordingLayout> layout_;  // replaced under frame_mutex_ (LayOut)
  std::shared_ptr<const scene::WorldModel> laid_out_;   // the compiled world layout_ was made from
  nlohmann::json world_;                                // guarded by frame_mutex_
  std::unique_ptr<ValueLogger> logger_;
  std::string logger_file_;
  std::string logger_token_;    // the control token of the page that started the log
  std::chrono::steady_clock::time_point logger_start_;
  std::string logger_stopped_;  // why the last log ended by itself, "" = it did not
  std::string last_error_;  // why running stopped (a bad value), "" = none
  std::chrono::steady_clock::time_point run_start_wall_;
  // Real time spent running since the last reset (the page's time display): before the current run, and the
  // current run's start. Guarded by command_mutex_.
  double real_seconds_before_ = 0.0;
  std::chrono::steady_clock::time_point real_since_;
  double run_start_time_ = 0.0;

  // Commands for the stepping thread, and whether it should run.
  std::mutex command_mutex_;
  std::condition_variable_any command_posted_;  // also woken by the destructor's stop request
  std::vector<std::function<void()>> commands_;
  bool running_ = false;
  bool realtime_ = true;
  int pending_steps_ = 0;

  // The newest frame, for the pages.
  std::mutex frame_mutex_;
  std::condition_variable frame_published_;
  LiveFrame frame_;
  nlohmann::json state_;  // State() as of the newest frame

  // --osp: the gateway that steps the simulation in the stepping thread, the episode recorder, and the eventfd
  // that wakes the gateway's poll when a command is posted (the command service polls it).
  class CommandService;
  std::unique_ptr<osp::EpisodeRecorder> recorder_;
  std::unique_ptr<CommandService> command_service_;
  std::unique_ptr<osp::OspGateway> gateway_;
  std::string osp_endpoint_;  // the OSP server's address, for State()
  int wake_fd_ = -1;

  // Who controls.
  std::mutex token_mutex_;
  std::string token_;
  std::chrono::steady_clock::time_point token_seen_;

  std::jthread thread_;  // last: the stepping thread (Loop) or, with --osp, the gateway's
};

/// Whether `file` is a plain file name [A-Za-z0-9_.-]{1,64} ending in `extension` (".val", ".csv").
bool IsSafeFileName(const std::string& file, const char* extension);

}  // namespace orcs::viewer
