#include "model/core/value_file.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "base/near_names.h"
#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/text_file.h"

namespace orcs {
namespace {

constexpr std::string_view kInclude = "#include";

void ReadInto(const std::filesystem::path& file, int depth, std::vector<ValueAssignment>& out);

// "#include <other.val>" or "#include other.val"; the file name relative to the including file.
void ReadInclude(const std::filesystem::path& file, int line_number, std::string_view line, int depth,
                 std::vector<ValueAssignment>& out) {
  std::string_view name = text::Trim(line.substr(kInclude.size()));
  if (name.size() >= 2 && name.front() == '<' && name.back() == '>') name = text::Trim(name.substr(1, name.size() - 2));
  if (name.empty()) throw InputError(file.string(), line_number, "#include expected a file name, found nothing");
  if (depth + 1 > ValueFile::kMaxIncludeDepth) {
    throw InputError(file.string(), line_number,
                     "#include nested deeper than " + std::to_string(ValueFile::kMaxIncludeDepth) +
                         " files (an include cycle?)");
  }
  const std::filesystem::path included = file.parent_path() / std::string(name);
  if (!std::filesystem::is_regular_file(included)) {
    throw InputError(file.string(), line_number, "#include: cannot read '" + included.string() + "'");
  }
  ReadInto(included, depth + 1, out);
}

void ReadInto(const std::filesystem::path& file, int depth, std::vector<ValueAssignment>& out) {
  std::istringstream in(ReadTextFile(file.string()));  // a regular file within the input bound, or an InputError
  std::string raw;
  for (int line_number = 1; std::getline(in, raw); ++line_number) {
    // A value file is lines of text: a control character (a NUL, a stray carriage return, an escape) is nothing a
    // saved file holds, and is refused rather than guessed at. A CR ending the line (a CRLF file) is allowed.
    std::string_view unterminated = raw;
    if (!unterminated.empty() && unterminated.back() == '\r') unterminated.remove_suffix(1);
    if (const std::size_t at = FindControlCharacter(unterminated); at != std::string_view::npos) {
      throw InputError(file.string(), line_number,
                       "control character " + ControlCharacterName(unterminated[at]) + " at column " +
                           std::to_string(at + 1) + ": a value file holds one 'path=value' of text per line");
    }
    const std::string_view line = text::Trim(raw);
    if (line.starts_with(kInclude) &&
        (line.size() == kInclude.size() || !std::isalnum(static_cast<unsigned char>(line[kInclude.size()])))) {
      ReadInclude(file, line_number, line, depth, out);
      continue;
    }
    if (line.empty() || line.front() == '#') continue;
    const size_t equals = line.find('=');
    if (equals == std::string_view::npos) {
      throw InputError(file.string(), line_number, "expected 'path=value', found " + text::Quote(line));
    }
    const std::string_view path = text::Trim(line.substr(0, equals));
    if (path.empty()) throw InputError(file.string(), line_number, "expected a path before '=', found nothing");
    out.push_back({std::string(path), std::string(text::Trim(line.substr(equals + 1))), file.string(), line_number});
  }
}

}  // namespace

std::size_t FindControlCharacter(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if ((byte < 0x20 && byte != '\t') || byte == 0x7f) return i;
  }
  return std::string_view::npos;
}

std::string ControlCharacterName(char c) {
  const auto byte = static_cast<unsigned char>(c);
  char code[8];
  std::snprintf(code, sizeof code, "U+%04X", byte);
  switch (byte) {
    case 0x00: return std::string(code) + " (NUL)";
    case 0x0a: return std::string(code) + " (line feed)";
    case 0x0d: return std::string(code) + " (carriage return)";
    case 0x1b: return std::string(code) + " (escape)";
    case 0x7f: return std::string(code) + " (delete)";
    default: return code;
  }
}

std::vector<ValueAssignment> ValueFile::Read(const std::string& file) {
  std::vector<ValueAssignment> assignments;
  ReadInto(file, 0, assignments);
  return assignments;
}

void ValueFile::Apply(const std::string& file, VariableRepository& repository) {
  ApplyAssignments(Read(file), repository);
}

namespace {

// Every path of the repository, for "did you mean".
std::vector<std::string> PathsOf(const VariableRepository& repository) {
  std::vector<std::string> paths;
  paths.reserve(static_cast<std::size_t>(repository.size()));
  for (int id = 0; id < repository.size(); ++id) paths.push_back(repository.path(id));
  return paths;
}

}  // namespace

IgnoredValues ValueFile::Apply(const std::string& file, VariableRepository& repository, UnknownPaths unknown) {
  std::vector<ValueAssignment> assignments = Read(file);
  IgnoredValues ignored;
  std::vector<std::string> paths;  // the repository's, once a path is unknown
  if (unknown == UnknownPaths::kIgnore) {
    std::erase_if(assignments, [&](const ValueAssignment& assignment) {
      if (repository.Find(assignment.path) != nullptr) return false;
      if (IsOriginalGuiPath(assignment.path)) {
        ignored.original.push_back(assignment);
      } else {
        // Only the first few are named in the warning: only those are worth the search.
        std::string near;
        if (ignored.unknown.size() < IgnoredValues::kNamed) {
          if (paths.empty()) paths = PathsOf(repository);
          near = DidYouMean(assignment.path, paths, 2);
        }
        ignored.unknown_near.push_back(near);
        ignored.unknown.push_back(assignment);
      }
      return true;
    });
  }
  ApplyAssignments(assignments, repository);
  return ignored;
}

bool IsOriginalGuiPath(std::string_view path) {
  // The original's and its successor's GUI state: windows, cameras, the OpenGL view, plotters, loggers, plug-ins.
  static constexpr std::string_view kPrefixes[] = {
      "/GUI/",     "/Gui/",    "/OpenGL/",       "/Camera", "/Viewer/",     "/Visualization/", "/Plugins/",
      "/PlugIns/", "/Logger/", "/ValuePlotter/", "/Plotter/", "/DebugOutput/"};
  for (const std::string_view prefix : kPrefixes) {
    if (path.starts_with(prefix)) return true;
  }
  return false;
}

void IgnoredValues::Add(const IgnoredValues& more) {
  original.insert(original.end(), more.original.begin(), more.original.end());
  unknown.insert(unknown.end(), more.unknown.begin(), more.unknown.end());
  unknown_near.insert(unknown_near.end(), more.unknown_near.begin(), more.unknown_near.end());
}

std::string IgnoredValues::Warning() const {
  const auto name = [](const std::vector<ValueAssignment>& list, const std::vector<std::string>* near = nullptr) {
    std::string out;
    for (std::size_t i = 0; i < list.size() && i < kNamed; ++i) {
      out += (i > 0 ? ", " : "") + list[i].path + " (" + list[i].file + ":" + std::to_string(list[i].line) + ")";
      if (near != nullptr && i < near->size() && !(*near)[i].empty()) out += (*near)[i].substr(1, (*near)[i].size() - 2);
    }
    if (list.size() > kNamed) out += " and " + std::to_string(list.size() - kNamed) + " more";
    return out;
  };
  std::string line = "warning: ignored " + std::to_string(original.size() + unknown.size()) + " value(s) orcs has no use for";
  if (!original.empty()) line += "; of the original's GUI, cameras or plug-ins: " + name(original);
  if (!unknown.empty()) line += "; unknown to orcs: " + name(unknown, &unknown_near);
  return line + " (--strict refuses a file with such values)";
}

void ValueFile::ApplyAssignments(const std::vector<ValueAssignment>& assignments, VariableRepository& repository) {
  // Check everything first, so that a bad line leaves the repository as it was.
  for (const ValueAssignment& assignment : assignments) {
    const Value* value = repository.Find(assignment.path);
    if (value == nullptr) {
      throw InputError(assignment.file, assignment.line,
                       "unknown repository path " + text::Quote(assignment.path) +
                           DidYouMean(assignment.path, PathsOf(repository), 3));
    }
    if (const std::string expected = value->CheckString(assignment.value); !expected.empty()) {
      throw InputError(assignment.file, assignment.line,
                       assignment.path + ": expected " + expected + ", found " + text::Quote(assignment.value));
    }
  }
  for (const ValueAssignment& assignment : assignments) repository.Set(assignment.path, assignment.value);
}

void ValueFile::Save(const std::string& file, const VariableRepository& repository, const std::string& saved_at,
                     const std::string& regular_expression) {
  AtomicFile out(file);
  out.stream() << "#ORCS Values\n#Saved at: " << saved_at << "\n";
  for (int id : repository.Match(regular_expression)) {
    // A value is one line: a line feed in a string value would add lines — assignments — that loading applies.
    // Such a value cannot be written, and nothing is (the temporary file is dropped).
    const std::string value = repository.value(id).ToString();
    if (const std::size_t at = FindControlCharacter(value); at != std::string::npos) {
      throw InputError(file, 0,
                       repository.path(id) + ": the value holds control character " +
                           ControlCharacterName(value[at]) + ", which a value file cannot hold; nothing was saved");
    }
    out.stream() << repository.path(id) << "=" << value << "\n";
  }
  out.Commit();
}

}  // namespace orcs
