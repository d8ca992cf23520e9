#include "model/identify/open_parameter_probe.h"

#include <algorithm>
#include <cmath>

#include "model/identify/replay_objective.h"

namespace orcs::identify {
namespace {

// Whether a probed value's fit loss is as good as the fitted point's, within the allowed ratio (in RMS terms).
bool FitsAsWell(double loss, double fitted_loss, const OpenProbeOptions& options) {
  if (!std::isfinite(loss) || loss >= ReplayObjective::kFailedPoint) return false;
  const double ratio = options.loss == Loss::kSquared ? options.equivalent_ratio * options.equivalent_ratio
                                                      : options.equivalent_ratio;
  return loss <= ratio * fitted_loss;
}

}  // namespace

std::vector<double> ProbeValues(const FitParameter& parameter, double value, double ci95) {
  std::vector<double> raw;
  if (std::isfinite(ci95)) {
    for (double k : {-1.0, -0.5, 0.5, 1.0}) raw.push_back(value + k * ci95);
  } else {
    for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) raw.push_back(FromUnit(parameter, u));
  }
  const double resolution = 1e-9 * (parameter.upper - parameter.lower);
  std::vector<double> values;
  for (double v : raw) {
    v = std::clamp(v, parameter.lower, parameter.upper);
    if (std::abs(v - value) <= resolution) continue;
    if (!values.empty() && std::abs(v - values.back()) <= resolution) continue;
    values.push_back(v);
  }
  return values;
}

OpenProbeResult ProbeOpenParameters(ReplayEvaluator& replays, const std::vector<ReplayRun>& fit,
                                    const std::vector<ReplayRun>& holdout, const std::vector<FitParameter>& parameters,
                                    const std::vector<Override>& fixed, std::size_t first_probed,
                                    const std::vector<double>& values, const std::vector<double>& ci95,
                                    const std::vector<bool>& identified, double fit_loss, double holdout_loss,
                                    const OpenProbeOptions& options) {
  OpenProbeResult result{values, fit_loss, holdout_loss, {}};
  const ReplayObjective fit_objective(replays, fit, fixed, options.loss);
  const ReplayObjective holdout_objective(replays, holdout, fixed, options.loss);
  for (std::size_t i = first_probed; i < parameters.size(); ++i) {
    if (identified[i]) continue;
    const std::vector<double> probed = ProbeValues(parameters[i], result.values[i], ci95[i]);
    if (probed.empty()) continue;
    std::vector<std::vector<Override>> points;
    for (double v : probed) {
      std::vector<double> point = result.values;
      point[i] = v;
      points.push_back(OverridesOf(parameters, point));
    }
    const std::vector<double> fit_losses = fit_objective.Losses(points);
    const std::vector<double> holdout_losses = holdout_objective.Losses(points);
    OpenParameter open;
    open.path = parameters[i].path;
    open.unit = parameters[i].unit;
    open.fitted = result.values[i];
    open.ci95 = ci95[i];
    open.low = std::min(probed.front(), open.fitted);
    open.high = std::max(probed.back(), open.fitted);
    open.probed = static_cast<int>(probed.size());
    open.chosen = open.fitted;
    open.fit_loss = result.fit_loss;
    open.holdout_loss_fitted = result.holdout_loss;
    open.holdout_loss = result.holdout_loss;
    for (std::size_t k = 0; k < probed.size(); ++k) {
      // Compared with the fit's own point, so that moves of several open parameters cannot drift away from it.
      if (!FitsAsWell(fit_losses[k], fit_loss, options)) continue;
      ++open.equivalent;
      if (holdout_losses[k] < open.holdout_loss) {
        open.chosen = probed[k];
        open.fit_loss = fit_losses[k];
        open.holdout_loss = holdout_losses[k];
      }
    }
    result.values[i] = open.chosen;
    result.fit_loss = open.fit_loss;
    result.holdout_loss = open.holdout_loss;
    result.open.push_back(std::move(open));
  }
  return result;
}

}  // namespace orcs::identify
