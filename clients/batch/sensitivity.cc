#include "clients/batch/sensitivity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

namespace orcs::batch {
using runtime::SweepValue;
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// Groups of sample indices, one per bin, numbers in increasing order: boundaries at round(k·N/B), each moved up
// past values equal to the one before it so that ties share a bin.
std::vector<std::vector<std::size_t>> NumericBins(const std::vector<SweepValue>& x, int bins) {
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&x](std::size_t a, std::size_t b) { return x[a].number < x[b].number; });
  std::vector<std::vector<std::size_t>> groups;
  const std::size_t n = order.size();
  std::size_t start = 0;
  for (int k = 1; k <= bins && start < n; ++k) {
    std::size_t end =
        k == bins ? n : static_cast<std::size_t>(std::llround(static_cast<double>(k) * static_cast<double>(n) / bins));
    end = std::max(end, start + 1);
    while (end < n && x[order[end]].number == x[order[end - 1]].number) ++end;
    groups.emplace_back(order.begin() + static_cast<std::ptrdiff_t>(start),
                        order.begin() + static_cast<std::ptrdiff_t>(end));
    start = end;
  }
  return groups;
}

// One group per category, in the axis's order (the category's index).
std::vector<std::vector<std::size_t>> CategoryBins(const std::vector<SweepValue>& x) {
  std::map<double, std::vector<std::size_t>> by_index;
  for (std::size_t i = 0; i < x.size(); ++i) by_index[x[i].number].push_back(i);
  std::vector<std::vector<std::size_t>> groups;
  for (auto& [index, members] : by_index) groups.push_back(std::move(members));
  return groups;
}

// Under no effect (and normal noise) S = SS_between / SS_total ~ Beta((B − 1)/2, (N − B)/2): mean (B − 1)/(N − 1),
// variance 2(B − 1)(N − B) / ((N − 1)²(N + 1)).
double NoiseFloor(double bins, double n) {
  if (n < 2) return 0.0;
  const double mean = (bins - 1) / (n - 1);
  const double variance = 2 * (bins - 1) * (n - bins) / ((n - 1) * (n - 1) * (n + 1));
  return std::min(1.0, mean + 2 * std::sqrt(std::max(0.0, variance)));
}

}  // namespace

int DefaultBinCount(std::size_t samples) {
  return std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(samples)))));
}

Sensitivity FirstOrderSensitivity(const std::vector<SweepValue>& x, const std::vector<double>& y, int bins) {
  if (x.size() != y.size()) throw std::invalid_argument("FirstOrderSensitivity: x and y differ in length");
  Sensitivity result;
  const std::size_t n = y.size();
  if (n == 0) {
    result.index = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  const bool categorical = std::any_of(x.begin(), x.end(), [](const SweepValue& v) { return v.categorical(); });
  const std::vector<std::vector<std::size_t>> groups =
      categorical ? CategoryBins(x) : NumericBins(x, std::max(1, bins));
  const double mean = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(n);
  double total = 0.0;
  for (double value : y) total += (value - mean) * (value - mean);
  double between = 0.0;
  for (const std::vector<std::size_t>& group : groups) {
    SensitivityBin bin;
    bin.count = static_cast<int>(group.size());
    double sum = 0.0;
    bin.low = bin.high = x[group.front()].number;
    for (std::size_t i : group) {
      sum += y[i];
      bin.low = std::min(bin.low, x[i].number);
      bin.high = std::max(bin.high, x[i].number);
    }
    bin.mean = sum / static_cast<double>(group.size());
    bin.label = categorical ? x[group.front()].text
                            : (bin.low == bin.high ? Number(bin.low) : Number(bin.low) + ".." + Number(bin.high));
    between += static_cast<double>(group.size()) * (bin.mean - mean) * (bin.mean - mean);
    result.bins.push_back(std::move(bin));
  }
  // Var(Y) = 0: every sample gave the same fitness, and no parameter explains anything. (Compared as values, not
  // through `total`, which rounding can leave a hair above 0 for equal outputs.)
  const auto [lowest, highest] = std::minmax_element(y.begin(), y.end());
  result.index = *lowest == *highest ? std::numeric_limits<double>::quiet_NaN() : std::min(1.0, between / total);
  result.noise_floor = NoiseFloor(static_cast<double>(result.bins.size()), static_cast<double>(n));
  return result;
}

}  // namespace orcs::batch
