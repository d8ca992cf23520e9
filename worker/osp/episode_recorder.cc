#include "worker/osp/episode_recorder.h"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "model/core/error.h"

namespace orcs::osp {

EpisodeRecorder::EpisodeRecorder(const scene::Simulation& simulation, EpisodeRecorderOptions options)
    : simulation_(simulation), options_(std::move(options)) {
  std::error_code error;
  std::filesystem::create_directories(options_.folder, error);
  if (error) throw InputError(options_.folder, 0, "cannot make the recordings' folder: " + error.message());
  Begin();
}

EpisodeRecorder::~EpisodeRecorder() {
  try {
    End();
  } catch (const std::exception& error) {  // a destructor must not throw: the log says what was lost
    if (options_.log) options_.log(std::string("the last episode's recording was not written: ") + error.what());
  }
}

void EpisodeRecorder::Sample() {
  if (!recorder_) return;
  recorder_->Sample();
  if (recorder_->frame_count() >= options_.max_frames) {
    if (options_.log) {
      options_.log("episode " + std::to_string(episode_) + " reached " + std::to_string(options_.max_frames) +
                   " frames: its recording ends here (the simulation runs on)");
    }
    End();
  }
}

void EpisodeRecorder::NextEpisode() {
  End();
  Begin();
}

void EpisodeRecorder::Begin() {
  ++episode_;
  if (episode_ > options_.max_episodes) {
    if (episode_ == options_.max_episodes + 1 && options_.log) {
      options_.log("recorded " + std::to_string(options_.max_episodes) + " episodes: later ones are not recorded");
    }
    return;
  }
  recorder_ = std::make_unique<evaluation::Recorder>(
      simulation_, evaluation::RecordingSource{"orcs-osp", options_.environment, "", 0, 0, nullptr});
}

void EpisodeRecorder::End() {
  if (!recorder_) return;
  const std::string file = FileOf(episode_);
  const std::int64_t frames = recorder_->frame_count();
  const std::string bytes = recorder_->Finish();
  recorder_.reset();
  evaluation::WriteRecording(file, bytes);
  ++written_;
  if (options_.log) options_.log("recorded episode " + std::to_string(episode_) + ": " + file + ", " +
                                 std::to_string(frames) + " frames");
}

std::string EpisodeRecorder::FileOf(int episode) const {
  char name[32];
  std::snprintf(name, sizeof name, "episode-%04d.orcsrec", episode);
  return (std::filesystem::path(options_.folder) / name).string();
}

}  // namespace orcs::osp
