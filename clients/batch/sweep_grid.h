// The grid of `orcs-batch sweep`: one axis per --param PATH=LOW:HIGH:STEPS (or PATH=V1,V2,... for a list of
// categories), every combination a point. The axes of a Latin hypercube sweep (PATH=LOW:HIGH) are parsed here too;
// their points come from latin_hypercube.h.
#pragma once

#include <string>
#include <vector>

#include "clients/runtime/batch_input.h"

namespace orcs::batch {

/// How a sweep chooses its points: every combination of the axes' values, or a Latin hypercube sample.
enum class SweepSampling { kGrid, kLatinHypercube };

/// One swept repository value.
struct SweepAxis {
  std::string path;  ///< repository path, e.g. "/AngularMotor/PID/Proportional"
  double low = 0.0;  ///< first value, in the path's unit (a categorical axis: 0)
  double high = 0.0; ///< last value (≥ low) (a categorical axis: the last category's index)
  /// number of values, evenly spaced from low to high; 1 = low only. A categorical axis: its number of categories;
  /// a Latin hypercube interval: 0 (continuous).
  int steps = 1;
  /// the values of a categorical axis (PATH=V1,V2,...) as the repository reads them, e.g. material names; empty
  /// for a numeric axis
  std::vector<std::string> categories;
  bool categorical() const { return !categories.empty(); }
  /// The i-th value, 0 ≤ i < steps; the last is exactly `high`.
  double ValueAt(int i) const;
  /// The i-th grid value as a point carries it: ValueAt(i), or the i-th category.
  runtime::SweepValue GridValue(int i) const;
};

/// Parses one --param. For the grid "PATH=LOW:HIGH:STEPS"; for a Latin hypercube "PATH=LOW:HIGH"; for either a list
/// of values "PATH=V1,V2,..." (categories, e.g. /Sim/Floor/Material=PVC,Wood,Carpet). Throws InputError
/// "--param 'text': ..." naming what is wrong: no '=', a path not starting with '/', numbers that do not parse or
/// are not finite, LOW above HIGH, STEPS not an integer in 1..10000, STEPS of 1 with LOW ≠ HIGH, the wrong number
/// of ':' fields for the sampling, an empty or repeated value in a list, or a material name (a path ending in
/// "/Material") that the material table does not know.
SweepAxis ParseSweepAxis(const std::string& text, SweepSampling sampling = SweepSampling::kGrid);

/// Throws InputError when a path is swept twice.
void CheckDistinctPaths(const std::vector<SweepAxis>& axes);

/// Every combination of the axes' values, the first axis varying slowest. Throws InputError when a path is
/// swept twice or the grid exceeds `max_points`.
std::vector<runtime::SweepPoint> SweepGrid(const std::vector<SweepAxis>& axes, std::size_t max_points = 1000000);

}  // namespace orcs::batch
