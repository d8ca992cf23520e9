#include "base/log_sink.h"

#include <iostream>

namespace orcs {

void WriteLogLine(const LogSink& sink, std::string_view program, std::string_view line) {
  if (sink) {
    sink(line);
  } else {
    std::cerr << program << ": " << line << '\n';  // std::cerr is unbuffered: the line is out at once
  }
}

}  // namespace orcs
