// The folder `orcs-robot --view DIR` keeps for orcs-view to follow while the robot moves (docs/hardware.md,
// "Watching a run"): robot.orcsrec — the robot model posed by the measured angles, with the commands, one frame per
// control period; twin.orcsrec — the simulated twin fed the same commands, one frame per period; robot_run.json —
// what runs on what; progress.json — how far it is (docs/batch.md's progress file, command "robot"). The recordings
// are flushed (Recorder::TakeFlushed) and progress.json replaced twice a second, so a reader sees every period up
// to the last flush. Watching never stops the robot: a folder that cannot be written is said once and left.
#pragma once

#include <chrono>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "hardware/robot/joint_map.h"
#include "hardware/robot/robot_session.h"
#include "hardware/robot/simulated_twin.h"
#include "model/evaluation/recorder.h"

namespace orcs::hardware {

class RobotRunFolder {
 public:
  /// Creates `folder` (and its parents) and writes robot_run.json with `about` (map, played, port, rate_hz,
  /// duration_s) plus the joints; the robot's model is built in `environment` ("" = the default world). Throws
  /// InputError naming the folder when it cannot be made, before anything moves.
  RobotRunFolder(const std::string& folder, const JointMap& map, const std::string& environment,
                 const nlohmann::json& about);
  ~RobotRunFolder();

  /// One control period's row, its command sent; `twin` (or null) still at the row's time.
  void Add(const RobotRow& row, SimulatedTwin* twin);
  /// The run has ended: the recordings are finished and progress.json says how.
  void Finish(const RobotRun& run);

  const std::string& folder() const { return folder_; }

 private:
  void Flush();
  void WriteProgress(const std::string& state, const std::string& stop);
  /// Appends `bytes` to the recording `name` of the folder (`file` open on it after the first piece).
  void Append(std::ofstream& file, const char* name, const std::string& bytes);
  void Fail(const std::string& what) noexcept;

  std::string folder_;
  nlohmann::json about_;                                 // robot_run.json's fields, for progress.json too
  SimulatedTwin robot_;                                  // the robot's model, posed by the measured angles
  std::unique_ptr<evaluation::Recorder> robot_recorder_;  // from the first row
  std::unique_ptr<evaluation::Recorder> twin_recorder_;   // from the first row, when there is a twin
  std::ofstream robot_file_;                             // robot.orcsrec, appended from the second flush on
  std::ofstream twin_file_;                              // twin.orcsrec, likewise
  std::size_t periods_ = 0;                              // rows added
  double time_ = 0.0;                                    // s, the last row's
  std::chrono::steady_clock::time_point last_flush_;     // wall clock: twice a second
  bool failed_ = false;                                  // a write failed: said once, nothing more written
};

}  // namespace orcs::hardware
