// The points of `orcs-batch sweep --sample lhs --samples N`: a Latin hypercube sample. Every axis is cut into N
// strata of equal width and every stratum holds exactly one sample; the strata of the axes are paired by a seeded
// permutation per axis, and each sample lies at a uniformly drawn place inside its stratum. A categorical axis
// (PATH=V1,V2,...) hands its N strata to its K values in K equal blocks, so every value is sampled N/K times
// (rounded down or up). Deterministic: the points depend on the axes, N and the seed alone.
#pragma once

#include <cstdint>
#include <vector>

#include "clients/batch/sweep_grid.h"
#include "clients/runtime/batch_input.h"

namespace orcs::batch {

/// N samples over the axes (parsed with SweepSampling::kLatinHypercube). Axis a draws its permutation, then its
/// offsets inside the strata, from its own stream (seed, "latin-hypercube", a), so adding an axis leaves the
/// others' values as they were. A numeric axis's values lie in [low, high]; stratum s of N is
/// [low + s·(high−low)/N, low + (s+1)·(high−low)/N). Throws InputError when a path is swept twice, `samples` is
/// outside 1..max_points, or a categorical axis has more values than there are samples.
std::vector<runtime::SweepPoint> LatinHypercube(const std::vector<SweepAxis>& axes, int samples, std::uint64_t seed,
                                       int max_points = 1000000);

}  // namespace orcs::batch
