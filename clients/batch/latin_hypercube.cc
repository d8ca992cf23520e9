#include "clients/batch/latin_hypercube.h"

#include <algorithm>
#include <numeric>

#include "model/core/error.h"
#include "model/core/random_stream.h"

namespace orcs::batch {
using runtime::SweepPoint;
using runtime::SweepValue;
namespace {

// Fisher–Yates with the stream's unbiased integers: stratum of each sample.
std::vector<int> Permutation(int n, RandomStream& stream) {
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  for (int i = n - 1; i > 0; --i) {
    const auto j = static_cast<int>(stream.UniformInt(static_cast<std::uint64_t>(i) + 1));
    std::swap(order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(j)]);
  }
  return order;
}

SweepValue NumericValue(const SweepAxis& axis, int stratum, int samples, RandomStream& stream) {
  const double fraction = (static_cast<double>(stratum) + stream.Uniform()) / static_cast<double>(samples);
  // Rounding may land a hair above `high` at the top stratum; the range is a promise.
  return std::min(axis.high, axis.low + (axis.high - axis.low) * fraction);
}

// Strata 0..N−1 go to the K categories in blocks: category floor(s·K/N).
SweepValue CategoryValue(const SweepAxis& axis, int stratum, int samples) {
  const auto count = static_cast<long long>(axis.categories.size());
  const auto index = static_cast<int>(static_cast<long long>(stratum) * count / samples);
  return SweepValue(axis.categories[static_cast<std::size_t>(index)], index);
}

}  // namespace

std::vector<SweepPoint> LatinHypercube(const std::vector<SweepAxis>& axes, int samples, std::uint64_t seed,
                                       int max_points) {
  CheckDistinctPaths(axes);
  if (samples < 1 || samples > max_points) {
    throw InputError("--samples", 0,
                     "expected 1 to " + std::to_string(max_points) + ", found " + std::to_string(samples));
  }
  std::vector<SweepPoint> points(static_cast<std::size_t>(samples), SweepPoint(axes.size()));
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const SweepAxis& axis = axes[a];
    if (axis.categorical() && axis.categories.size() > static_cast<std::size_t>(samples)) {
      throw InputError("--samples", 0,
                       std::to_string(samples) + " samples cannot hold the " + std::to_string(axis.categories.size()) +
                           " values of " + axis.path + ": every value needs at least one sample");
    }
    RandomStream stream(seed, "latin-hypercube", a);
    const std::vector<int> strata = Permutation(samples, stream);
    for (int n = 0; n < samples; ++n) {
      const int stratum = strata[static_cast<std::size_t>(n)];
      SweepValue value =
          axis.categorical() ? CategoryValue(axis, stratum, samples) : NumericValue(axis, stratum, samples, stream);
      points[static_cast<std::size_t>(n)][a] = {axis.path, std::move(value)};
    }
  }
  return points;
}

}  // namespace orcs::batch
