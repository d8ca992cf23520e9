#include "model/identify/replay_objective.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/demand.h"
#include "model/core/text.h"

namespace orcs::identify {

ReplayObjective::ReplayObjective(ReplayEvaluator& replays, const std::vector<ReplayRun>& runs,
                                 std::vector<Override> fixed, Loss loss)
    : replays_(replays), runs_(runs), fixed_(std::move(fixed)), loss_(loss) {}

double ReplayObjective::RunBound(double bound, const ReplayRun& run) const {
  double samples = 0.0;
  for (const ReplayRun& each : runs_) samples += static_cast<double>(each.samples);
  if (!std::isfinite(bound) || run.samples == 0) return std::numeric_limits<double>::infinity();
  // One run alone beyond this error puts the pooled loss above the bound, whatever the other runs give; the margin
  // keeps that true through the rounding of error² · samples (error · samples).
  constexpr double kRoundingMargin = 1e-9;
  const double share = bound * samples / static_cast<double>(run.samples);
  return (loss_ == Loss::kAbsolute ? share : std::sqrt(share)) * (1.0 + kRoundingMargin);
}

std::vector<double> ReplayObjective::Losses(const std::vector<std::vector<Override>>& points,
                                            const std::vector<double>& bounds) const {
  ORCS_DEMAND(bounds.empty() || bounds.size() == points.size());
  std::vector<ReplayRequest> requests;
  for (std::size_t p = 0; p < points.size(); ++p) {
    std::vector<Override> overrides = fixed_;
    overrides.insert(overrides.end(), points[p].begin(), points[p].end());
    for (const ReplayRun& run : runs_) {
      ReplayRequest& request = requests.emplace_back(ReplayRequest{&run, overrides});
      request.loss = loss_;
      if (!bounds.empty()) request.stop_above = RunBound(bounds[p], run);
    }
  }
  const std::vector<ReplayOutcome> outcomes = replays_.Replay(requests);
  std::vector<double> losses;
  std::size_t next = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    double sum = 0.0;
    double samples = 0.0;
    bool failed = false;
    for (const ReplayRun& run : runs_) {
      const ReplayOutcome& outcome = outcomes[next++];
      failed = failed || !outcome.ok || !std::isfinite(outcome.error);
      const double per_sample = loss_ == Loss::kAbsolute ? outcome.error : outcome.error * outcome.error;
      sum += per_sample * static_cast<double>(run.samples);
      samples += static_cast<double>(run.samples);
    }
    losses.push_back(failed || samples == 0.0 ? kFailedPoint : sum / samples);
  }
  return losses;
}

std::vector<std::vector<double>> ReplayObjective::Residuals(const std::vector<std::vector<Override>>& points) const {
  std::vector<ReplayRequest> requests;
  for (const std::vector<Override>& point : points) {
    std::vector<Override> overrides = fixed_;
    overrides.insert(overrides.end(), point.begin(), point.end());
    for (const ReplayRun& run : runs_) requests.push_back({&run, overrides, /*log=*/true});
  }
  const std::vector<ReplayOutcome> outcomes = replays_.Replay(requests);
  std::vector<std::vector<double>> residuals;
  std::size_t next = 0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    std::vector<double>& point = residuals.emplace_back();
    bool failed = false;
    for (const ReplayRun& run : runs_) {
      const ReplayOutcome& outcome = outcomes[next++];
      failed = failed || !outcome.ok;
      // The angles in degrees, then the accelerometer axes times their weights (deg per m/s²).
      const auto append = [&](const std::string& path, const std::vector<double>& measured, double weight) {
        const std::vector<double>* simulated = nullptr;
        for (const auto& [name, values] : outcome.columns) {
          if (name == path) simulated = &values;
        }
        if (simulated == nullptr || simulated->size() < measured.size()) {
          failed = true;
          return;
        }
        for (std::size_t row = 1; row < measured.size(); ++row) {
          point.push_back(weight * ((*simulated)[row] - measured[row]));
        }
      };
      for (const std::string& motor : run.channels) {
        append(MotorColumn(run.run->agent, motor, "JointAngle"), run.run->joint_angle.at(motor), 1.0);
      }
      for (std::size_t i = 0; i < run.accelerometers.size(); ++i) {
        append(AccelerometerColumn(run.run->agent, run.accelerometers[i]),
               run.run->acceleration.at(run.accelerometers[i]), run.acceleration_weights[i]);
      }
    }
    const bool finite = std::all_of(point.begin(), point.end(), [](double r) { return std::isfinite(r); });
    if (failed || !finite) point.clear();
  }
  return residuals;
}

std::vector<std::vector<double>> ReplayObjective::LossResiduals(
    const std::vector<std::vector<Override>>& points) const {
  std::vector<std::vector<double>> residuals = Residuals(points);
  if (loss_ == Loss::kAbsolute) {
    for (std::vector<double>& point : residuals) {
      for (double& r : point) r = std::copysign(std::sqrt(std::abs(r)), r);
    }
  }
  return residuals;
}

std::vector<Override> OverridesOf(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::vector<Override> overrides;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    overrides.emplace_back(parameters[i].path, text::FormatDouble(values[i]));
  }
  return overrides;
}

}  // namespace orcs::identify
