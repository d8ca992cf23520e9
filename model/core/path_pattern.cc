#include "model/core/path_pattern.h"

#include <re2/re2.h>

#include <string>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {

PathPattern::PathPattern(std::string_view regular_expression) {
  if (regular_expression.size() > kMaxLength) {
    throw InputError("regular expression of " + std::to_string(regular_expression.size()) + " characters: at most " +
                     std::to_string(kMaxLength) + " are accepted");
  }
  RE2::Options options;
  options.set_log_errors(false);
  pattern_ = std::make_unique<RE2>(re2::StringPiece(regular_expression.data(), regular_expression.size()), options);
  if (!pattern_->ok()) {
    // RE2's message repeats part of the expression: escaped too, so that the error stays one line.
    throw InputError("invalid regular expression " + text::Quote(regular_expression) + ": " +
                     text::Excerpt(pattern_->error()));
  }
}

PathPattern::~PathPattern() = default;
PathPattern::PathPattern(PathPattern&&) noexcept = default;
PathPattern& PathPattern::operator=(PathPattern&&) noexcept = default;

bool PathPattern::Matches(std::string_view path) const {
  return RE2::FullMatch(re2::StringPiece(path.data(), path.size()), *pattern_);
}

}  // namespace orcs
