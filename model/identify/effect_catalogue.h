// The effect catalogue of the gap workflow (docs/gap.md): for each switchable motor effect
// (model/aseries/motor_effects.h), what orcs-gap switches on, which of its parameters a fit adjusts and in which
// range, and the quantity its residual is plotted against.
#pragma once

#include <string_view>
#include <vector>

#include "model/identify/fit_parameter.h"

namespace orcs::identify {

/// One entry of the catalogue: what orcs-gap adds, fits and reports.
struct EffectDescription {
  std::string_view name;       ///< "Backlash": /Effects/<name>/Enabled switches it
  std::string_view summary;    ///< one line for reports
  std::string_view quantity;   ///< the signal its residual shows against (plot_gap.py): speed, velocity, load, ...
  std::vector<FitParameter> parameters;  ///< what a fit adjusts (other parameters keep their values); start unset
  bool with_original = true;  ///< tried by default on the original's motor model
  bool with_servo = true;     ///< tried (and allowed) on the physical servo model (/Servo/Enabled)
};

/// The catalogue, in a fixed order.
const std::vector<EffectDescription>& EffectCatalogue();
/// The catalogue entry called `name`, or nullptr.
const EffectDescription* FindEffect(std::string_view name);

}  // namespace orcs::identify
