// Reads a recording (docs/recording.md) whole into memory: the header, the frame times, every channel's values
// and the contacts. Every problem is an InputError naming the file: not a recording, a newer version, a bad
// header, a truncated stream.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "model/evaluation/recording_layout.h"

namespace orcs::evaluation {

/// One contact of one frame.
using RecordedContact = ContactSample;

struct Recording {
  nlohmann::json header;              ///< as stored
  std::vector<std::string> channels;  ///< header "channels"
  std::vector<double> times;          ///< per frame, simulated s
  std::vector<float> values;          ///< frame-major: frame f, channel c at f · channel_count + c
  std::vector<std::uint32_t> contact_offsets;  ///< frame f's contacts: [offsets[f], offsets[f+1])
  std::vector<RecordedContact> contacts;
  bool finished = true;  ///< false: the frame stream was cut (a run still being written; allow_unfinished)

  int frame_count() const { return static_cast<int>(times.size()); }
  int channel_count() const { return static_cast<int>(channels.size()); }
  float value(int frame, int channel) const { return values[std::size_t(frame) * channels.size() + channel]; }
  /// Index of a channel by name, or -1.
  int FindChannel(std::string_view name) const;
};

/// Limits on what a reader accepts, so a hostile file cannot take unbounded memory.
struct RecordingLimits {
  std::uint64_t max_file_bytes = std::uint64_t{1} << 30;          ///< the file, 1 GiB
  std::uint64_t max_decompressed_bytes = std::uint64_t{4} << 30;  ///< the frames inflated, 4 GiB
  /// Accept a frame stream that stops early — a recording still being written (Recorder::TakeFlushed) — and read the
  /// frames complete so far (Recording::finished false); otherwise that is an error, "truncated".
  bool allow_unfinished = false;
};

/// Parses a recording's bytes; `name` (a file name) prefixes every error.
Recording ParseRecording(std::string_view bytes, const std::string& name, const RecordingLimits& limits = {});
/// Reads a regular file. Throws InputError naming `path`.
Recording ReadRecording(const std::string& path, const RecordingLimits& limits = {});

}  // namespace orcs::evaluation
