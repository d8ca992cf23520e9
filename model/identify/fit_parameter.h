// One repository value a fit adjusts, with its search range: the model's base parameters (gap_diagnosis.cc) and
// the effect catalogue's parameters (effect_catalogue.h) alike.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

namespace orcs::identify {

struct FitParameter {
  std::string path;        ///< repository path
  std::string unit;        ///< for reports
  double lower = 0.0;      ///< search range, in the unit
  double upper = 0.0;
  bool log_scale = true;   ///< search log(value) (positive scale parameters)
  double start = 0.0;      ///< where the search starts (clamped into the range); set by whoever starts the fit
};

/// The value of `p` at its normalised coordinate u ∈ [0, 1] of the search box (log-scaled where p.log_scale).
inline double FromUnit(const FitParameter& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  return p.log_scale ? std::exp(std::log(p.lower) + u * (std::log(p.upper) - std::log(p.lower)))
                     : p.lower + u * (p.upper - p.lower);
}

/// The normalised coordinate of `value` (clamped into the range).
inline double ToUnit(const FitParameter& p, double value) {
  value = std::clamp(value, p.lower, p.upper);
  const double u = p.log_scale ? (std::log(value) - std::log(p.lower)) / (std::log(p.upper) - std::log(p.lower))
                               : (value - p.lower) / (p.upper - p.lower);
  return std::clamp(u, 0.0, 1.0);
}

}  // namespace orcs::identify
