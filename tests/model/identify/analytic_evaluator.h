// A cheap analytic stand-in for the replays of the gap workflow (tests of model_fit.h and replay_objective.h): each
// replay's RMS error (degrees) is computed from its overrides, so the fitter and the objective are tested without a
// broker or a physics engine.
#pragma once

#include <atomic>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "model/identify/replay_objective.h"

namespace orcs::identify::test {

// The hidden truth: /A = 2.0 (searched on a log scale over 0.1…10), /B = 0.3 (linear over −1…1).
constexpr double kTrueA = 2.0;
constexpr double kTrueB = 0.3;

// The analytic run's residual at row k (of `rows`) as a sum of three patterns, each with a mean square of 1 and
// orthogonal to the others over the run: da·√2·sin, db·√2·cos and floor·√2·sin of twice the frequency, so that the
// mean square of the residuals is da² + db² + floor², the RMS error squared.
inline double AnalyticResidual(double da, double db, double floor, std::size_t k, std::size_t rows) {
  constexpr double kTwoPi = 6.283185307179586;
  const double phase = kTwoPi * static_cast<double>(k) / static_cast<double>(rows);
  return std::sqrt(2.0) * (da * std::sin(phase) + db * std::cos(phase) + floor * std::sin(2.0 * phase));
}

// A run's RMS error: 10° per unit of log-distance in A and per unit of distance in B, plus the run's own floor
// (what no parameter can explain). A replay whose /A is negative "goes unstable". Asked for its log, a replay gives
// the motor's simulated angles, whose residuals against the run (all 0°) have that RMS: so the Levenberg–Marquardt
// polish works on it too.
class AnalyticEvaluator : public ReplayEvaluator {
 public:
  std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) override {
    std::vector<ReplayOutcome> outcomes;
    for (const ReplayRequest& request : requests) {
      std::map<std::string, double> values;
      for (const auto& [path, value] : request.overrides) values[path] = std::stod(value);
      const double a = values.count("/A") ? values["/A"] : 1.0;
      const double b = values.count("/B") ? values["/B"] : 0.0;
      const double floor = request.run->scenario.value("floor_deg", 0.0);
      ReplayOutcome outcome;
      outcome.ok = a >= 0;
      if (outcome.ok) {
        const double da = 10.0 * std::log(a / kTrueA), db = 10.0 * (b - kTrueB);
        outcome.error = std::sqrt(da * da + db * db + floor * floor);
        if (request.log) {
          const std::size_t rows = request.run->samples;
          std::vector<double> angles = {0.0};  // row 0, the state after the reset, is not compared
          for (std::size_t k = 1; k <= rows; ++k) angles.push_back(AnalyticResidual(da, db, floor, k, rows));
          outcome.columns.emplace_back("/Sim/Analytic/M/JointAngle", std::move(angles));
        }
        // A replay past its bound stops with the least lower bound it may give: just above the bound.
        if (outcome.error > request.stop_above) {
          outcome.error = std::nextafter(request.stop_above, std::numeric_limits<double>::infinity());
          outcome.stopped_early = true;
          ++stopped_;
        }
      }
      outcomes.push_back(outcome);
    }
    replays_ += requests.size();
    return outcomes;
  }
  std::uint64_t replays_run() const override { return replays_; }
  std::uint64_t replays_stopped_early() const override { return stopped_; }

 private:
  std::atomic<std::uint64_t> replays_{0};
  std::atomic<std::uint64_t> stopped_{0};
};

// A run of `samples` rows after the first of one motor "M", measured at 0° throughout. The measured runs live as
// long as the test program.
inline ReplayRun AnalyticRun(const std::string& name, std::size_t samples, double floor_deg) {
  static std::deque<MeasuredRun> measured;
  MeasuredRun& data = measured.emplace_back();
  data.source = name + ".csv";
  data.agent = "Analytic";
  data.motors = {"M"};
  data.joint_angle["M"].assign(samples + 1, 0.0);
  ReplayRun run;
  run.name = name;
  run.source = name + ".csv";
  run.run = &data;
  run.channels = {"M"};
  run.samples = samples;
  run.scenario = {{"agent", "Analytic"}, {"duration", 1.0}, {"floor_deg", floor_deg}};
  return run;
}

inline const std::vector<FitParameter> kParameters = {{"/A", "", 0.1, 10.0, true, 0.5}, {"/B", "", -1.0, 1.0, false, -0.5}};

}  // namespace orcs::identify::test
