// Parameters the fit runs leave open (docs/gap.md, "Parameters the fit runs leave open"): a candidate effect's
// parameter whose confidence interval is wider than its value moves along a direction the fit runs hardly see, so
// where in that interval its fit ends is chance, and the held-out runs may not be blind to it. A LuGre friction's
// bristle stiffness, 144.8 or 163.4 N·m/rad (± 264) after fits that match the fit run to the noise alike, replays
// the held-out run at 3.33° or at 0.25°: scored at one arbitrary point, the hidden effect lost to a wrong one.
// So each such parameter is probed across its interval, the others held at the fit's values; the values that fit
// the fit runs as well are the candidate's too, and the held-out runs choose among them — and the verdict says so.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "model/identify/fit_parameter.h"
#include "model/identify/probe_comparison.h"
#include "model/identify/replay.h"
#include "model/identify/replay_evaluator.h"

namespace orcs::identify {

/// One open parameter of a candidate, as probed.
struct OpenParameter {
  std::string path;          ///< repository path
  std::string unit;          ///< for reports
  double fitted = 0.0;       ///< where the fit ended, in the unit
  double ci95 = std::numeric_limits<double>::quiet_NaN();  ///< the fit's 95 % half-width; NaN = unseen: the whole range
  double low = 0.0;          ///< the lowest value probed, in the unit
  double high = 0.0;         ///< the highest value probed, in the unit
  int probed = 0;            ///< values probed besides the fitted one
  int equivalent = 0;        ///< of those, how many fit the fit runs as well (OpenProbeOptions::equivalent_ratio)
  double chosen = 0.0;       ///< the value the candidate keeps: the equivalent one the held-out runs fit best
  double fit_loss = 0.0;     ///< the fit runs' loss at the chosen value (deg², or deg with the absolute loss)
  double holdout_loss_fitted = 0.0;  ///< the held-out runs' loss at the fitted value
  double holdout_loss = 0.0;         ///< the held-out runs' loss at the chosen value
  /// The probe motion on which the model at the fitted and at the chosen value differ most: what would identify the
  /// parameter (filled in for a named effect whose value moved; probe "" otherwise)
  TellApart pin_down;
};

struct OpenProbeOptions {
  Loss loss = Loss::kSquared;  ///< the fits' and scores' loss
  /// A probed value fits the fit runs "as well" when its loss is within this factor of the fitted point's in RMS
  /// terms (squared for the squared loss): the tie the verdict allows between effects (kTieRatio).
  double equivalent_ratio = 1.0;
};

/// The point a candidate keeps after its open parameters are probed, and what was found.
struct OpenProbeResult {
  std::vector<double> values;       ///< every parameter's value, in the unit (the fit's, open ones maybe moved)
  double fit_loss = 0.0;            ///< the fit runs' loss there
  double holdout_loss = 0.0;        ///< the held-out runs' loss there
  std::vector<OpenParameter> open;  ///< each open parameter probed, in parameter order
};

/// Probes, one after the other, each parameter from `first_probed` on that `identified` says the fit runs leave
/// open: up to four values across its interval (value ± ci95 and ± ci95/2, clipped to its range; its whole range at
/// five even points when ci95 is NaN), the other parameters at `values`, `fixed` applied as in the fit. Each
/// probe is two batches of replays (fit and held-out runs). `fit_loss` and `holdout_loss` are those of `values`.
OpenProbeResult ProbeOpenParameters(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit,
                                    const std::vector<ReplayRun>& holdout, const std::vector<FitParameter>& parameters,
                                    const std::vector<Override>& fixed, std::size_t first_probed,
                                    const std::vector<double>& values, const std::vector<double>& ci95,
                                    const std::vector<bool>& identified, double fit_loss, double holdout_loss,
                                    const OpenProbeOptions& options);

/// The values probed for a parameter at `value` with half-width `ci95` (NaN = the whole range), in increasing
/// order, without `value` itself.
std::vector<double> ProbeValues(const FitParameter& parameter, double value, double ci95);

}  // namespace orcs::identify
