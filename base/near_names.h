// "Did you mean": the names near a mistyped one — an option ("--job" → "--jobs"), a motor ("Right/Hip" →
// "Right/HipPitch"), a value path. Shared by the command lines (net/) and the model's messages.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace orcs {

/// The fewest single-character insertions, deletions, substitutions and swaps of neighbours from `a` to `b` (optimal
/// string alignment: "jbos" is one edit from "jobs").
std::size_t EditDistance(std::string_view a, std::string_view b);

/// Up to `limit` of `candidates` near `name`, nearest first (ties in the candidates' order): a few letters off
/// (at most a quarter of the candidate's length, at least one), or beginning with `name` when it has 3 or more
/// characters ("Right/Hip" → "Right/HipPitch", "Right/HipRoll", "Right/HipYaw"). Empty when none is near.
std::vector<std::string> NearNames(std::string_view name, const std::vector<std::string>& candidates,
                                   std::size_t limit = 3);

/// NearNames as the end of a message: " (did you mean 'A', 'B' or 'C'?)", or "" when none is near.
std::string DidYouMean(std::string_view name, const std::vector<std::string>& candidates, std::size_t limit = 3);

}  // namespace orcs
