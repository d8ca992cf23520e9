// orcs-osp --record DIR (the original ClientSimulator's run, watched afterwards in orcs-view): each episode of the
// OSP-driven simulation — from one reset to the next — becomes its own recording, DIR/episode-0001.orcsrec,
// episode-0002.orcsrec, ..., written when the episode ends (the next reset, or the server stopping). An
// evolution client resets once per individual, so both the episodes and each one's frames are bounded; past a
// bound the recorder says so once in the log and records no more (the simulation runs on unchanged: recording
// only reads it).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "model/evaluation/recorder.h"
#include "model/scene/simulation.h"

namespace orcs::osp {

struct EpisodeRecorderOptions {
  std::string folder;                    ///< where the recordings go; created when missing
  std::string environment;               ///< the environment file, for the recordings' headers
  int max_episodes = 1000;               ///< episodes recorded at most; later ones are not
  std::int64_t max_frames = 60000;       ///< frames per episode at most (10 min at 100 steps/s); then it ends
  std::function<void(std::string_view)> log;  ///< one line each: a file written, a bound reached
};

class EpisodeRecorder {
 public:
  /// Starts the first episode's recording of `simulation` (built and reset; it must outlive the recorder).
  /// Throws InputError naming the folder when it cannot be made.
  EpisodeRecorder(const scene::Simulation& simulation, EpisodeRecorderOptions options);
  /// Writes the episode under way.
  ~EpisodeRecorder();
  EpisodeRecorder(const EpisodeRecorder&) = delete;
  EpisodeRecorder& operator=(const EpisodeRecorder&) = delete;

  /// After each step: a frame of the episode under way.
  void Sample();
  /// After each reset: writes the episode that ended and starts the next one.
  void NextEpisode();

  int episodes_written() const { return written_; }

 private:
  void Begin();
  void End();
  std::string FileOf(int episode) const;

  const scene::Simulation& simulation_;
  EpisodeRecorderOptions options_;
  std::unique_ptr<evaluation::Recorder> recorder_;  // the episode under way; null past a bound
  int episode_ = 0;   // the number of the episode under way, from 1
  int written_ = 0;
};

}  // namespace orcs::osp
