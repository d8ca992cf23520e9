#include "model/identify/probe_comparison.h"

#include <cmath>

#include "model/identify/probe_motion.h"

namespace orcs::identify {
namespace {

// The simulated angle of `path` in a replay's log; null when the replay failed or did not log it.
const std::vector<double>* Column(const ReplayOutcome& outcome, const std::string& path) {
  for (const auto& [name, values] : outcome.columns) {
    if (name == path) return &values;
  }
  return nullptr;
}

// RMS difference of two equally long traces; NaN when they cannot be compared.
double RmsDifference(const std::vector<double>* a, const std::vector<double>* b) {
  if (a == nullptr || b == nullptr || a->size() != b->size() || a->empty()) return std::nan("");
  double sum = 0.0;
  for (std::size_t row = 0; row < a->size(); ++row) sum += ((*a)[row] - (*b)[row]) * ((*a)[row] - (*b)[row]);
  return std::sqrt(sum / static_cast<double>(a->size()));
}

}  // namespace

TellApart CompareOnProbes(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                          const std::vector<ReplayRun>& fit, const std::string& motor,
                          const std::vector<Override>& first, const std::vector<Override>& second, double noise) {
  TellApart best;
  best.motor = motor;
  best.noise = noise;
  const std::vector<ProbeMotion> probes = ProbeMotions(rig, motor);
  std::vector<MeasuredRun> runs;
  for (const ProbeMotion& probe : probes) runs.push_back(ProbeRun(rig, probe, fit.empty() ? nullptr : fit[0].run));
  std::vector<ReplayRun> probe_replays;
  for (const MeasuredRun& run : runs) probe_replays.push_back(MakeReplayRun(rig, run, model));
  std::vector<ReplayRequest> requests;
  for (const ReplayRun& run : probe_replays) {
    requests.push_back({&run, first, /*log=*/true});
    requests.push_back({&run, second, /*log=*/true});
  }
  const std::vector<ReplayOutcome> outcomes = replays.Replay(requests);
  const std::string path = MotorColumn(rig.agent, motor, "JointAngle");
  best.difference = -1.0;
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const double rms = RmsDifference(Column(outcomes[2 * k], path), Column(outcomes[2 * k + 1], path));
    if (std::isfinite(rms) && rms > best.difference) {
      best.difference = rms;
      best.probe = probes[k].name;
      best.description = probes[k].description;
      best.shows = probes[k].shows;
    }
  }
  if (best.difference < 0.0) best.difference = 0.0;
  return best;
}

}  // namespace orcs::identify
