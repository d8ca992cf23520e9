// A simple variance-based sensitivity of a sweep's fitness to each swept parameter: the first-order index
// S = Var(E[Y|X]) / Var(Y), estimated by binning X (docs/batch.md, "Robustness report"). E[Y|X] is taken as the mean
// of Y over each bin of X — equal-count bins for a number, one bin per value for a category — so S is the share
// of Y's variance that the bin means explain (the correlation ratio η²). Plain statistics, no model.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "clients/runtime/batch_input.h"

namespace orcs::batch {

/// One bin of an input's values and the output's mean over it.
struct SensitivityBin {
  std::string label;  ///< the category, or "LOW..HIGH" of the numbers in the bin
  double low = 0.0;   ///< smallest input value in the bin (a category: its index on the axis)
  double high = 0.0;  ///< largest input value in the bin (a category: its index)
  int count = 0;      ///< samples in the bin
  double mean = 0.0;  ///< mean output over the bin's samples: the estimate of E[Y | X in the bin]
};

/// The first-order sensitivity of an output to one input.
struct Sensitivity {
  /// S = Σ_b n_b (ȳ_b − ȳ)² / Σ_i (y_i − ȳ)², 0…1; NaN when the output does not vary (or there are no samples)
  double index = 0.0;
  /// The S an input without any effect stays below about 97 % of the time with B bins and N samples: the mean
  /// (B − 1)/(N − 1) plus twice the standard deviation of S under no effect (S ~ Beta((B − 1)/2, (N − B)/2) for
  /// normal noise). An index below it cannot be told from no effect. 0 when N < 2.
  double noise_floor = 0.0;
  std::vector<SensitivityBin> bins;  ///< in increasing input order (categories: in the axis's order)
};

/// Bins for N samples of a numeric input: round(√N), at least 1 — the usual compromise between bins too wide to
/// follow E[Y|X] and bins too small for their means to settle.
int DefaultBinCount(std::size_t samples);

/// Estimates S for the input values `x` (numbers, or categories: SweepValue::categorical) against the outputs `y`
/// (same length, finite). Numbers go into `bins` bins of equal count in increasing order, except that equal values
/// never straddle two bins (so a grid's value is one bin when there are no more values than bins); categories are
/// one bin each. Throws std::invalid_argument when the lengths differ.
Sensitivity FirstOrderSensitivity(const std::vector<runtime::SweepValue>& x, const std::vector<double>& y, int bins);

}  // namespace orcs::batch
