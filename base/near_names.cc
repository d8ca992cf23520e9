#include "base/near_names.h"

#include <algorithm>
#include <utility>

namespace orcs {

std::size_t EditDistance(std::string_view a, std::string_view b) {
  // Optimal string alignment: three rows of the table suffice.
  std::vector<std::size_t> before(b.size() + 1), previous(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      row[j] = std::min({previous[j] + 1, row[j - 1] + 1, previous[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, row);
  }
  return previous[b.size()];
}

std::vector<std::string> NearNames(std::string_view name, const std::vector<std::string>& candidates,
                                   std::size_t limit) {
  std::vector<std::pair<std::size_t, std::size_t>> near;  // (distance, index)
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const std::string& candidate = candidates[i];
    if (candidate == name) continue;
    const std::size_t distance = EditDistance(name, candidate);
    const bool few_letters_off = distance <= std::max<std::size_t>(1, candidate.size() / 4);
    const bool begins = name.size() >= 3 && candidate.starts_with(name);
    if (few_letters_off || begins) near.emplace_back(distance, i);
  }
  std::stable_sort(near.begin(), near.end());
  std::vector<std::string> names;
  for (std::size_t k = 0; k < near.size() && k < limit; ++k) names.push_back(candidates[near[k].second]);
  return names;
}

std::string DidYouMean(std::string_view name, const std::vector<std::string>& candidates, std::size_t limit) {
  const std::vector<std::string> names = NearNames(name, candidates, limit);
  if (names.empty()) return "";
  std::string text = " (did you mean ";
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) text += k + 1 == names.size() ? " or " : ", ";
    text += "'" + names[k] + "'";
  }
  return text + "?)";
}

}  // namespace orcs
