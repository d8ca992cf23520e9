// The robustness report of `orcs-batch sweep` for its one controller (docs/batch.md, "Robustness report"): how the
// fitness is distributed over the swept points (mean, standard deviation, quartiles, the worst point) and how
// much of its variance each swept parameter explains (sensitivity.h). Written as DIR/robustness.json and
// DIR/robustness.md; the ranking also goes to stdout.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "clients/batch/sensitivity.h"
#include "clients/batch/sweep_grid.h"
#include "clients/batch/sweep_report.h"

namespace orcs::batch {

/// The fitness over the points that ran ok (a point's fitness: the mean over its ok repeats).
struct FitnessDistribution {
  int points = 0;          ///< points in the sweep
  int ok_points = 0;       ///< points with at least one ok repeat: the sample the figures below describe
  double mean = 0.0;       ///< mean fitness (NaN when no point ran ok, as every figure here)
  double deviation = 0.0;  ///< sample standard deviation (divided by N − 1; 0 for one point)
  double min = 0.0;        ///< lowest fitness
  double q1 = 0.0;         ///< first quartile (linear between order statistics, as the scenario's "quantile")
  double median = 0.0;     ///< second quartile
  double q3 = 0.0;         ///< third quartile
  double max = 0.0;        ///< highest fitness
};

/// One swept parameter's first-order sensitivity.
struct ParameterSensitivity {
  std::string path;          ///< the swept repository path
  bool categorical = false;  ///< whether its values are categories (one bin each)
  Sensitivity sensitivity;   ///< S, its noise floor and the bins
};

struct RobustnessReport {
  std::string title;                              ///< what was swept, e.g. the scenario's name
  SweepSampling sampling = SweepSampling::kGrid;  ///< how the points were chosen
  FitnessDistribution fitness;                    ///< over the ok points
  std::optional<std::size_t> worst;               ///< index of the point with the lowest fitness, if any ran ok
  std::vector<ParameterSensitivity> parameters;   ///< in axis order
  std::vector<std::size_t> ranking;               ///< indices into `parameters`, highest S first (NaN last)
};

/// Computes the report from the sweep's rows (SweepRows). Points without an ok repeat are counted, not used.
RobustnessReport MakeRobustnessReport(const std::string& title, SweepSampling sampling,
                                      const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows);

/// "most sensitive to /Sim/Floor/Material (S 0.62), then /AngularMotor/PID/Proportional (S 0.21), ..." — one line.
std::string RankingText(const RobustnessReport& report);

/// A few lines for stdout: the fitness distribution, the worst point and the ranking.
std::string RobustnessSummary(const RobustnessReport& report, const std::vector<SweepRow>& rows);

/// Writes FOLDER/robustness.json and FOLDER/robustness.md (each to a temporary name, then renamed). Throws
/// InputError when they cannot be written.
void WriteRobustnessReport(const std::string& folder, const RobustnessReport& report,
                           const std::vector<SweepRow>& rows);

}  // namespace orcs::batch
