// A user's regular expression over repository paths (RE2 syntax, matching the whole path): what
// VariableRepository::Match, a randomisation's "match" and the OSP gateway's patterns share. RE2 runs in time
// linear in the path's length whatever the pattern, so that no user's expression can hang a simulator, a gateway
// or a viewer ((.*)*(.*)*X takes std::regex minutes).
#pragma once

#include <cstddef>
#include <memory>
#include <string_view>

namespace re2 {
class RE2;
}

namespace orcs {

class PathPattern {
 public:
  /// Compiles `regular_expression`. Throws InputError for an invalid expression or one longer than kMaxLength.
  explicit PathPattern(std::string_view regular_expression);
  ~PathPattern();
  PathPattern(PathPattern&&) noexcept;
  PathPattern& operator=(PathPattern&&) noexcept;

  /// Whether the expression matches the whole of `path`.
  bool Matches(std::string_view path) const;

  /// The longest expression accepted, characters.
  static constexpr std::size_t kMaxLength = 1000;

 private:
  std::unique_ptr<re2::RE2> pattern_;
};

}  // namespace orcs
