#include "broker/broker_text.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "base/log_sink.h"

namespace orcs::broker {

std::string EscapeForLog(std::string_view line) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  text.reserve(std::min(line.size(), kMaxLogLine));
  for (unsigned char c : line) {
    if (text.size() >= kMaxLogLine) {
      text += "... (cut)";
      break;
    }
    if (c < 0x20 || c == 0x7f || c == '\\') {
      text += "\\x";
      text += kDigits[c >> 4];
      text += kDigits[c & 0xf];
    } else {
      text += static_cast<char>(c);
    }
  }
  return text;
}

void WriteLog(const LogSink& sink, const std::string& line) {
  WriteLogLine(sink, "orcs-broker", EscapeForLog(line));
}

std::string_view Utf8Prefix(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t end = max_bytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;  // inside a character
  return text.substr(0, end);
}

std::string Hex(const std::string& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text = "0x";
  for (unsigned char c : bytes) {
    text += kDigits[c >> 4];
    text += kDigits[c & 0xf];
  }
  return text;
}

std::string Seconds(std::chrono::steady_clock::duration duration) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", std::chrono::duration<double>(duration).count());
  return text;
}

double SecondsBetween(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

}  // namespace orcs::broker
