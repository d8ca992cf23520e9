// Value files (.val) of the original (spec/osp.md "Value files"): lines "path=value", trimmed; '#' starts a
// comment; "#include <file>" loads another file relative to the including one; booleans are T/F. Saved files
// begin with a "#ORCS Values" header and a "#Saved at:" line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "model/core/variable_repository.h"

namespace orcs {

/// The index of the first control character in `text` — a byte U+0000–U+001F other than a tab, or U+007F — or npos:
/// what one line of a value file cannot hold (a line feed or CR would start another line).
std::size_t FindControlCharacter(std::string_view text);

/// "U+000A (line feed)", "U+0000 (NUL)", "U+001B (escape)": how an error names a control character.
std::string ControlCharacterName(char c);

/// One "path=value" line, with where it came from (for error messages).
struct ValueAssignment {
  std::string path;   ///< repository path, trimmed
  std::string value;  ///< value text, trimmed
  std::string file;   ///< file the line is in
  int line = 0;       ///< 1-based line number
};

/// What Apply does with a path the repository lacks (docs/formats.md, "Value files of the original").
enum class UnknownPaths {
  kRefuse,  ///< an InputError naming the file and line (--strict; scenarios and jobs always)
  kIgnore,  ///< left out and returned, for one warning (an old value file of the original loads)
};

/// The assignments Apply left out: values of the original's GUI, cameras and plug-ins, then other unknown paths.
struct IgnoredValues {
  std::vector<ValueAssignment> original;  ///< paths under a prefix of the original's GUI (IsOriginalGuiPath)
  std::vector<ValueAssignment> unknown;   ///< every other path the repository lacks
  std::vector<std::string> unknown_near;  ///< per unknown path: " (did you mean '...'?)", or "" (searched for a file's first kNamed only)
  static constexpr std::size_t kNamed = 5;  ///< paths the warning names; the rest are counted
  bool empty() const { return original.empty() && unknown.empty(); }
  void Add(const IgnoredValues& more);
  /// One line for stderr: how many were ignored, each path with its file and line (the first few), and the fix.
  std::string Warning() const;
};

/// Whether `path` is a value of the original's GUI, cameras or plug-ins (/GUI/, /OpenGL/, /Camera..., /Plugins/,
/// ...; docs/formats.md), which orcs has no use for: the viewer keeps its cameras itself.
bool IsOriginalGuiPath(std::string_view path);

class ValueFile {
 public:
  /// Reads a value file and everything it includes, in order. Throws InputError naming the file and line for
  /// an unreadable file, a line without '=', an empty path, a control character (other than a tab, or a CR
  /// ending the line), a malformed or missing #include, or includes nested deeper than kMaxIncludeDepth (an
  /// include cycle).
  static std::vector<ValueAssignment> Read(const std::string& file);

  /// Reads a value file and applies every assignment to `repository`, in order. Throws InputError naming the
  /// file and line for an unknown path or a value that does not parse; the repository is left unchanged then
  /// (the whole file is checked before anything is set).
  static void Apply(const std::string& file, VariableRepository& repository);

  /// Apply with a choice for paths the repository lacks: refused as above, or left out and returned.
  static IgnoredValues Apply(const std::string& file, VariableRepository& repository, UnknownPaths unknown);

  /// Applies assignments (from Read, or inlined into a job) as Apply does: all checked first, then set in order.
  static void ApplyAssignments(const std::vector<ValueAssignment>& assignments, VariableRepository& repository);

  /// Writes every value whose path matches `regular_expression` (all by default) to `file`, via a temporary
  /// name and a rename. `saved_at` is the text of the "#Saved at:" line. Throws InputError when the file cannot
  /// be written, or naming the path when a value holds a control character (text::FindControlCharacter: a line
  /// feed would add lines to the file) — then nothing is written.
  static void Save(const std::string& file, const VariableRepository& repository, const std::string& saved_at,
                   const std::string& regular_expression = ".*");

  static constexpr int kMaxIncludeDepth = 16;
};

}  // namespace orcs
