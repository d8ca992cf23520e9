// The KeyFrameSniffer / KeyFramePlayer record of the original (spec/osp.md): text, one keyframe per line,
// comma-separated; `#` starts a comment. Field 0 is the time in milliseconds since reset, then one value per
// agent input in input order — for motor k: DesiredAngle (degrees), then DesiredTorque (−1…1).
//
// The older variant has the same number of columns but a different order and unit: time, then every motor's
// normalised angle (−1…1), then every motor's normalised torque (0…1). Which one a file is (docs/formats.md):
//   - a comment line "# layout: raw" or "# layout: normalised" says so explicitly;
//   - otherwise the file is the older layout exactly when every value lies within −1…1 (a raw record of a
//     moving robot has angles beyond one degree), and raw otherwise.
// Records are converted to the raw layout when read, so the player has one form only.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace orcs::control {

enum class KeyframeLayout {
  kRaw,         ///< time, then (DesiredAngle degrees, DesiredTorque −1…1) per motor
  kNormalised,  ///< time, then every normalised angle (−1…1), then every normalised torque (0…1)
};

/// One row of a record.
struct Keyframe {
  double time_ms = 0.0;        ///< simulated milliseconds since reset at which the row takes effect
  std::vector<double> inputs;  ///< raw inputs in input order: angle (degrees), torque (−1…1) per motor
  int line = 0;                ///< line of the source file, for messages
};

/// A whole record, in the raw layout.
struct KeyframeRecord {
  std::string source;                              ///< file name it was read from, for messages
  KeyframeLayout layout = KeyframeLayout::kRaw;    ///< the layout of the file as read (rows are raw)
  bool layout_detected = false;                    ///< true: no "# layout:" comment, the layout was inferred
  int motor_count = 0;                             ///< motors per row (row width = 1 + 2 · motor_count)
  std::vector<Keyframe> frames;                    ///< rows in file order; times never decrease
};

/// Parses a record for an agent with `motor_count` motors. Throws InputError "source:line: ..." for a row
/// with the wrong number of columns, a non-numeric or non-finite field, a negative time, a time earlier than
/// the row before, an unknown layout comment, or a record without rows.
KeyframeRecord ParseKeyframeRecord(std::string_view text, const std::string& source, int motor_count);

/// "1 motor", "21 motors": for messages.
std::string Motors(int count);

/// Reads and parses a record file; an unreadable file is an InputError naming it.
KeyframeRecord ReadKeyframeRecord(const std::string& path, int motor_count);

/// The record as text in the raw layout with a "# layout: raw" line after `comments` (each written as
/// "# comment"); numbers round-trip exactly. ParseKeyframeRecord(FormatKeyframeRecord(r)) gives r's rows.
std::string FormatKeyframeRecord(const KeyframeRecord& record, const std::vector<std::string>& comments);

}  // namespace orcs::control
