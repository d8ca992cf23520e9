// Records a simulation run for orcs-view (docs/recording.md): the RecordingLayout's header once, then every step's
// channel values and contacts, deflated into one zlib stream. The recorder only reads the simulation, so a
// recorded run has the same bits as an unrecorded one.
//
//   Recorder recorder(simulation, source);   // after Build() and Reset(): takes frame 0
//   while (...) { simulation.Step(); recorder.Sample(); }
//   WriteRecording(path, recorder.Finish());
#pragma once

#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

#include "model/evaluation/recording_layout.h"

namespace orcs::evaluation {

/// The format version this orcs writes and the newest it reads; docs/recording.md says when it changes.
inline constexpr std::uint32_t kRecordingVersion = 1;
/// "ORCSREC" and 0x1A.
inline constexpr char kRecordingMagic[8] = {'O', 'R', 'C', 'S', 'R', 'E', 'C', '\x1a'};

class Recorder {
 public:
  /// Starts recording `simulation` (built and reset) and takes frame 0.
  Recorder(const scene::Simulation& simulation, const RecordingSource& source);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Appends a frame with the simulation's current time, values and contacts.
  void Sample();
  /// The same with another time stamp, s: a kinematic replay that poses the robot after a Reset() per sample
  /// (orcs-gap's measured runs) stamps each frame with the sample's time.
  void SampleAt(double time);
  /// Flushes the frames so far (a zlib sync flush) and hands over the bytes made since the last call, the prefix and
  /// the header first: appended to a file in order, they make a recording that a reader with
  /// RecordingLimits::allow_unfinished opens whole up to the last frame (a run still going on, watched live).
  std::string TakeFlushed();
  /// Ends the stream and returns the file's bytes not yet taken (all of them without TakeFlushed()). The recorder is
  /// spent afterwards.
  std::string Finish();

  int channel_count() const { return layout_.channel_count(); }
  std::int64_t frame_count() const { return frames_; }

 private:
  void Deflate(const void* data, std::size_t size, int flush);

  const scene::Simulation& simulation_;
  RecordingLayout layout_;
  std::vector<float> values_;                  // this frame's values, reused
  std::vector<std::uint32_t> previous_;        // the previous frame's float bits
  std::vector<ContactSample> contacts_;        // this frame's contacts, reused
  std::vector<unsigned char> frame_;           // this frame's bytes, reused
  std::string out_;                            // the file so far
  z_stream stream_{};
  std::int64_t frames_ = 0;
  bool finished_ = false;
};

/// Writes a recording's bytes to `path` atomically (a temporary name, then renamed). Throws InputError naming
/// the file when it cannot be written.
void WriteRecording(const std::string& path, const std::string& bytes);

}  // namespace orcs::evaluation
