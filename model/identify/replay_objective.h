// What every fit of the gap workflow minimises (docs/gap.md, "How a fit works"): the replays of a set of measured
// runs under candidate points, each point's replays one batch for the ReplayEvaluator, pooled into the mean squared
// (or, with Loss::kAbsolute, the mean absolute) joint-angle error over all runs and channels. The swarm and compass
// search (model_fit.h) ask for losses, the Levenberg–Marquardt polish (least_squares_polish.h) for residuals.
#pragma once

#include <string>
#include <vector>

#include "model/identify/fit_parameter.h"
#include "model/identify/replay.h"
#include "model/identify/replay_evaluator.h"

namespace orcs::identify {

/// The replays of a set of runs, evaluated as one batch per call.
class ReplayObjective {
 public:
  /// `fixed` is applied to every replay after the model (e.g. an effect's Enabled switch); `loss` says how the
  /// angle errors are pooled.
  ReplayObjective(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs, std::vector<Override> fixed,
                  Loss loss = Loss::kSquared);

  /// The pooled loss of every point, in order: the mean squared error (deg²) or the mean absolute error (deg) over
  /// all runs, channels and rows. A point whose replay fails (unstable physics) scores kFailedPoint. `bounds`
  /// (empty, or one per point; +∞ = none): a point whose loss is sure to exceed its bound may have its replays
  /// stopped early, and then scores a lower bound of its loss that is above the bound.
  std::vector<double> Losses(const std::vector<std::vector<Override>>& points,
                             const std::vector<double>& bounds = {}) const;

  /// Per point, the residuals of every run's channels at every row after the first, in run and channel order:
  /// simulated − measured joint angle (degrees), then each accelerometer axis's simulated − measured reading times
  /// its weight (ReplayRun::acceleration_weights, degrees per m/s²); empty for a point whose replay failed.
  std::vector<std::vector<double>> Residuals(const std::vector<std::vector<Override>>& points) const;

  /// The residuals whose mean square is the loss, for a least-squares polish: Residuals itself for the squared
  /// loss, sign(r)·√|r| for the absolute one.
  std::vector<std::vector<double>> LossResiduals(const std::vector<std::vector<Override>>& points) const;

  Loss loss() const { return loss_; }

  static constexpr double kFailedPoint = 1e6;

 private:
  /// The error (degrees, in the loss's norm) above which `run` alone puts the pooled loss above `bound`; +∞ for no
  /// bound.
  double RunBound(double bound, const ReplayRun& run) const;

  ReplayEvaluator& replays_;
  const std::vector<ReplayRun>& runs_;
  std::vector<Override> fixed_;
  Loss loss_;
};

/// The assignments of `values` to `parameters`' paths.
std::vector<Override> OverridesOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values);

}  // namespace orcs::identify
