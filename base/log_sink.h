// Where a component's log lines go. Libraries that log (the broker, its clients' and workers' connections, the OSP
// server) take a LogSink from their owner: tests collect the lines, programs print them. Without one, a line goes
// to stderr prefixed by the program's name, the way every orcs program prints its own.
#pragma once

#include <functional>
#include <string_view>

namespace orcs {

/// Takes one log line, without its newline.
using LogSink = std::function<void(std::string_view)>;

/// Gives `line` to `sink`, or, when `sink` is empty, writes "`program`: `line`" and a newline to stderr.
void WriteLogLine(const LogSink& sink, std::string_view program, std::string_view line);

}  // namespace orcs
