#include "hardware/robot/robot_run_folder.h"

#include <unistd.h>

#include <ctime>
#include <filesystem>
#include <iostream>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/scene/simulation.h"

namespace orcs::hardware {
namespace {

namespace fs = std::filesystem;

constexpr auto kFlushEvery = std::chrono::milliseconds(500);  // how fresh orcs-view's picture is

std::string Path(const std::string& folder, const char* name) { return (fs::path(folder) / name).string(); }

void WriteJson(const std::string& path, const nlohmann::json& json) {
  AtomicFile file(path);
  file.stream() << json.dump(2) << "\n";
  file.Commit();
}

std::string MadeFolder(const std::string& folder) {
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder)) {
    throw InputError(folder, 0, "--view: cannot make the folder (" + error.message() + ")");
  }
  return folder;
}

}  // namespace

RobotRunFolder::RobotRunFolder(const std::string& folder, const JointMap& map, const std::string& environment,
                               const nlohmann::json& about)
    : folder_(MadeFolder(folder)), about_(about), robot_(environment, map) {
  about_["joints"] = nlohmann::json::array();
  for (const JointMapping& joint : map.joints) about_["joints"].push_back(joint.joint);
  about_["agent"] = map.agent;
  about_["environment"] = environment.empty() ? "the default world" : environment;
  // The robot's model reads its pose exactly: no sensor noise on the measured angles.
  robot_.simulation().repository().Get("/AngularMotor/IncludeNoise").Set(false);
  WriteJson(Path(folder_, "robot_run.json"), about_);
  WriteProgress("running", "");
  std::error_code ignored;  // an earlier run's recordings are not this one's
  fs::remove(Path(folder_, "robot.orcsrec"), ignored);
  fs::remove(Path(folder_, "twin.orcsrec"), ignored);
  last_flush_ = std::chrono::steady_clock::now();
}

RobotRunFolder::~RobotRunFolder() = default;

void RobotRunFolder::Add(const RobotRow& row, SimulatedTwin* twin) {
  if (failed_) return;
  try {
    robot_.Pose(row.angle, row.goal);
    if (!robot_recorder_) {
      robot_recorder_ = std::make_unique<evaluation::Recorder>(
          robot_.simulation(), evaluation::RecordingSource{"orcs-robot", about_.value("environment", ""),
                                                           "robot (measured)", 0, 0, nullptr});
      if (twin != nullptr) {
        twin_recorder_ = std::make_unique<evaluation::Recorder>(
            twin->simulation(), evaluation::RecordingSource{"orcs-robot", about_.value("environment", ""),
                                                            "twin (simulated)", 0, 0, nullptr});
      }
    } else {
      robot_recorder_->SampleAt(row.time);
      if (twin_recorder_ && twin != nullptr) twin_recorder_->SampleAt(row.time);
    }
    ++periods_;
    time_ = row.time;
    if (std::chrono::steady_clock::now() - last_flush_ >= kFlushEvery) Flush();
  } catch (const std::exception& error) {
    Fail(error.what());
  }
}

void RobotRunFolder::Flush() {
  Append(robot_file_, "robot.orcsrec", robot_recorder_->TakeFlushed());
  if (twin_recorder_) Append(twin_file_, "twin.orcsrec", twin_recorder_->TakeFlushed());
  WriteProgress("running", "");
  last_flush_ = std::chrono::steady_clock::now();
}

void RobotRunFolder::Finish(const RobotRun& run) {
  if (failed_) return;
  try {
    if (robot_recorder_) Append(robot_file_, "robot.orcsrec", robot_recorder_->Finish());
    if (twin_recorder_) Append(twin_file_, "twin.orcsrec", twin_recorder_->Finish());
    robot_file_.close();
    twin_file_.close();
    const char* state = run.reason == StopReason::kFinished      ? "finished"
                        : run.reason == StopReason::kInterrupted ? "interrupted"
                                                                 : "failed";
    WriteProgress(state, run.message);
  } catch (const std::exception& error) {
    Fail(error.what());
  }
}

void RobotRunFolder::Append(std::ofstream& file, const char* name, const std::string& bytes) {
  const std::string path = Path(folder_, name);
  if (!file.is_open()) {  // the first piece (signature, header, first frames) appears whole: a reader never sees less
    AtomicFile first(path);
    first.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    first.Commit();
    file.open(path, std::ios::binary | std::ios::app);
  } else {
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  file.flush();
  if (!file) throw InputError(folder_, 0, "--view: a recording could not be written (disk full?)");
}

void RobotRunFolder::WriteProgress(const std::string& state, const std::string& stop) {
  nlohmann::json progress = {{"format", "orcs-progress"},
                             {"version", 1},
                             {"command", "robot"},
                             {"state", state},
                             {"updated_unix", static_cast<double>(std::time(nullptr))},
                             {"pid", static_cast<long>(getpid())},
                             {"periods", periods_},
                             {"time_s", time_},
                             {"label", about_.value("played", "")}};
  if (about_.contains("duration_s")) progress["duration_s"] = about_["duration_s"];
  if (!stop.empty()) progress["stop"] = stop;
  WriteJson(Path(folder_, "progress.json"), progress);
}

void RobotRunFolder::Fail(const std::string& what) noexcept {
  failed_ = true;
  std::cerr << "orcs-robot: --view " << folder_ << ": " << what << "; the run goes on without it\n";
}

}  // namespace orcs::hardware
