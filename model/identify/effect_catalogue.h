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
  bool switched = true;       ///< switched on by /Effects/<name>/Enabled; false: its parameters are the robot's values
  /// A property of one link, chosen per diagnosis (LinkMass: /Sim/<agent>/<link>/Mass); `parameters` is empty and
  /// the diagnosis builds the link's from the model's value.
  bool per_link = false;
  /// Shows mainly in the accelerometers: tried by default only when the runs have accelerometer columns.
  bool needs_accelerometers = false;
};

/// Two effects that can explain the same data (docs/gap.md, "When two effects explain the data"): said with a
/// verdict that names both.
struct EffectRelation {
  std::string_view first;    ///< an effect's name
  std::string_view second;   ///< another's
  bool nested = false;       ///< `first` contains `second` exactly (a value of its extra parameters gives it)
  std::string_view text;     ///< how they relate, one clause
};

/// The catalogue, in a fixed order.
const std::vector<EffectDescription>& EffectCatalogue();
/// The catalogue entry called `name`, or nullptr.
const EffectDescription* FindEffect(std::string_view name);
/// How `a` and `b` relate (in either order), or nullptr when the catalogue says nothing of them.
const EffectRelation* FindRelation(std::string_view a, std::string_view b);

}  // namespace orcs::identify
