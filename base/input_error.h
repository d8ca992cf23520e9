// Bad user input, the first of orcs's two tiers of checks (docs/architecture.md, "Errors and bad input"; the second
// is base/demand.h): every input is checked where it enters, and refused with one line naming the source (a file, or
// a field of a message), the line where there is one, what was expected and what was found:
// "scenarios/x.xml:12: object 'Box': attribute 'mass' expected a number, found 'abc'". Here, at the bottom, so that
// every layer — the broker and the connection layer too — refuses input the same way and every program's main ends
// the same way (net/cli_style.h's RunProgram: exit 2).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace orcs {

/// Bad input from a user: a file, a command-line option, a message. Command-line programs print what()
/// and exit with code 2.
class InputError : public std::runtime_error {
 public:
  /// @param source  file name or field path the problem is in ("" when there is none).
  /// @param line    1-based line number, or 0 when the source has no lines.
  /// @param what    the problem, naming what was expected and what was found.
  InputError(std::string source, int line, const std::string& what)
      : std::runtime_error(Format(source, line, what)), source_(std::move(source)), line_(line) {}

  explicit InputError(const std::string& what) : InputError("", 0, what) {}

  const std::string& source() const { return source_; }
  int line() const { return line_; }

 private:
  static std::string Format(const std::string& source, int line, const std::string& what) {
    if (source.empty()) return what;
    if (line <= 0) return source + ": " + what;
    return source + ":" + std::to_string(line) + ": " + what;
  }

  std::string source_;
  int line_ = 0;
};

}  // namespace orcs
