#include "model/control/keyframe_record.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "model/aseries/value_range.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs::control {
namespace {

constexpr std::string_view kLayoutComment = "layout:";

// "layout: raw" inside a comment selects the layout; any other comment is free text.
std::optional<KeyframeLayout> LayoutComment(std::string_view comment, const std::string& source, int line) {
  const std::string_view body = text::Trim(comment);
  if (text::ToLower(body.substr(0, kLayoutComment.size())) != kLayoutComment) return std::nullopt;
  const std::string value = text::ToLower(text::Trim(body.substr(kLayoutComment.size())));
  if (value == "raw") return KeyframeLayout::kRaw;
  if (value == "normalised" || value == "normalized") return KeyframeLayout::kNormalised;
  throw InputError(source, line, "'# layout:' expected 'raw' or 'normalised', found " + text::Quote(value));
}

}  // namespace

std::string Motors(int count) { return std::to_string(count) + (count == 1 ? " motor" : " motors"); }

namespace {

Keyframe ParseRow(std::string_view row, const std::string& source, int line, int motor_count) {
  const std::vector<std::string_view> fields = text::Split(row, ',');
  const size_t expected = 1 + 2 * static_cast<size_t>(motor_count);
  if (fields.size() != expected) {
    throw InputError(source, line,
                     "expected " + std::to_string(expected) + " columns (time in ms, then DesiredAngle and "
                     "DesiredTorque of " + Motors(motor_count) + "), found " +
                         std::to_string(fields.size()));
  }
  Keyframe frame;
  frame.line = line;
  frame.inputs.reserve(expected - 1);
  for (size_t column = 0; column < fields.size(); ++column) {
    const std::optional<double> number = text::ParseDouble(text::Trim(fields[column]));
    if (!number || !std::isfinite(*number)) {
      throw InputError(source, line,
                       "column " + std::to_string(column + 1) + " expected a finite number, found " +
                           text::Quote(text::Trim(fields[column])));
    }
    if (column == 0) {
      frame.time_ms = *number;
    } else {
      frame.inputs.push_back(*number);
    }
  }
  if (frame.time_ms < 0) {
    throw InputError(source, line, "column 1 expected a time ≥ 0 ms, found " + text::FormatDouble(frame.time_ms));
  }
  return frame;
}

bool AllWithinUnitRange(const std::vector<Keyframe>& frames) {
  return std::all_of(frames.begin(), frames.end(), [](const Keyframe& frame) {
    return std::all_of(frame.inputs.begin(), frame.inputs.end(), [](double v) { return std::abs(v) <= 1.0; });
  });
}

// Older layout (every normalised angle, then every normalised torque) → raw interleaved layout.
void ConvertNormalisedToRaw(KeyframeRecord& record) {
  const auto motors = static_cast<size_t>(record.motor_count);
  for (Keyframe& frame : record.frames) {
    std::vector<double> raw(2 * motors);
    for (size_t m = 0; m < motors; ++m) {
      raw[2 * m] = aseries::kDesiredAngleRange.ToRaw(frame.inputs[m]);
      raw[2 * m + 1] = aseries::kDesiredTorqueRange.ToRaw(frame.inputs[motors + m]);
    }
    frame.inputs = std::move(raw);
  }
}

}  // namespace

KeyframeRecord ParseKeyframeRecord(std::string_view text, const std::string& source, int motor_count) {
  KeyframeRecord record;
  record.source = source;
  record.motor_count = motor_count;
  std::optional<KeyframeLayout> declared;
  int line = 0;
  for (std::string_view rest = text; !rest.empty() || line == 0;) {
    const size_t end = rest.find('\n');
    std::string_view content = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    ++line;
    const size_t hash = content.find('#');
    if (hash != std::string_view::npos) {
      if (auto layout = LayoutComment(content.substr(hash + 1), source, line)) declared = layout;
      content = content.substr(0, hash);
    }
    content = text::Trim(content);
    if (content.empty()) continue;
    Keyframe frame = ParseRow(content, source, line, motor_count);
    if (!record.frames.empty() && frame.time_ms < record.frames.back().time_ms) {
      throw InputError(source, line,
                       "time goes backwards: " + text::FormatDouble(frame.time_ms) + " ms after " +
                           text::FormatDouble(record.frames.back().time_ms) + " ms on line " +
                           std::to_string(record.frames.back().line));
    }
    record.frames.push_back(std::move(frame));
  }
  if (record.frames.empty()) throw InputError(source, 0, "expected at least one keyframe row, found none");
  record.layout_detected = !declared.has_value();
  record.layout = declared.value_or(AllWithinUnitRange(record.frames) ? KeyframeLayout::kNormalised
                                                                      : KeyframeLayout::kRaw);
  if (record.layout == KeyframeLayout::kNormalised) ConvertNormalisedToRaw(record);
  return record;
}

KeyframeRecord ReadKeyframeRecord(const std::string& path, int motor_count) {
  return ParseKeyframeRecord(ReadTextFile(path), path, motor_count);
}

std::string FormatKeyframeRecord(const KeyframeRecord& record, const std::vector<std::string>& comments) {
  std::string out;
  for (const std::string& comment : comments) out += "# " + comment + "\n";
  out += "# layout: raw\n";
  for (const Keyframe& frame : record.frames) {
    out += text::FormatDouble(frame.time_ms);
    for (double input : frame.inputs) out += "," + text::FormatDouble(input);
    out += "\n";
  }
  return out;
}

}  // namespace orcs::control
