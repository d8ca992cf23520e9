// One repository value a fit adjusts, with its search range: the model's base parameters (gap_diagnosis.cc) and
// the effect catalogue's parameters (effect_catalogue.h) alike.
#pragma once

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

}  // namespace orcs::identify
