// The grid of `orcs-batch sweep`: one axis per --param PATH=LOW:HIGH:STEPS, every combination a point.
#pragma once

#include <string>
#include <vector>

#include "clients/batch/batch_input.h"

namespace orcs::batch {

/// One swept repository value.
struct SweepAxis {
  std::string path;  ///< repository path, e.g. "/AngularMotor/PID/Proportional"
  double low = 0.0;  ///< first value, in the path's unit
  double high = 0.0; ///< last value (≥ low)
  int steps = 1;     ///< number of values, evenly spaced from low to high; 1 = low only
  /// The i-th value, 0 ≤ i < steps; the last is exactly `high`.
  double ValueAt(int i) const;
};

/// Parses "PATH=LOW:HIGH:STEPS". Throws InputError "--param 'text': ..." naming what is wrong: no '=', a path
/// not starting with '/', numbers that do not parse or are not finite, LOW above HIGH, STEPS not an integer in
/// 1..10000, or STEPS of 1 with LOW ≠ HIGH.
SweepAxis ParseSweepAxis(const std::string& text);

/// Every combination of the axes' values, the first axis varying slowest. Throws InputError when a path is
/// swept twice or the grid exceeds `max_points`.
std::vector<SweepPoint> SweepGrid(const std::vector<SweepAxis>& axes, std::size_t max_points = 1000000);

}  // namespace orcs::batch
