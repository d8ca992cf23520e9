// Text the broker writes about its peers: log lines (escaped and bounded, so that no peer can forge or flood one),
// routing ids in hex and durations. Shared by the core and the ZeroMQ shell.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "base/log_sink.h"

namespace orcs::broker {

/// Bytes of one log line, escapes included; a longer line is cut.
inline constexpr std::size_t kMaxLogLine = 2000;

/// The line with control characters and invalid bytes as \xNN, cut at kMaxLogLine bytes.
std::string EscapeForLog(std::string_view line);
/// Writes one escaped log line to `sink`, or to stderr prefixed "orcs-broker: " when `sink` is empty.
void WriteLog(const LogSink& sink, const std::string& line);
/// The first `max_bytes` bytes of `text` (well-formed UTF-8, as every protobuf string the broker receives), fewer
/// when that would cut a character in two: a cut character would not survive the client's UTF-8 check. (The same
/// rule as model/core/text.h's Prefix, which the broker may not link: docs/architecture.md.)
std::string_view Utf8Prefix(std::string_view text, std::size_t max_bytes);
/// "0x0080000001": a routing id for the log.
std::string Hex(const std::string& bytes);
/// "2.5 s".
std::string Seconds(std::chrono::steady_clock::duration duration);
/// `to` − `from` in seconds.
double SecondsBetween(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to);

}  // namespace orcs::broker
