// orcs-gap's replays as jobs: the gap workflow's ReplayEvaluator (model/identify/replay_evaluator.h) on top of a
// runtime::JobEvaluator, the broker in use. Each replay is one ordinary scenario job whose fitness term
// "measured_error" is the replay's RMS error; its log carries the simulated joint angles and motor torques.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "clients/runtime/job_evaluator.h"
#include "model/identify/replay_evaluator.h"
#include "orcs/v1/job.pb.h"

namespace orcs::gap {

class BrokerReplays : public identify::ReplayEvaluator {
 public:
  explicit BrokerReplays(runtime::JobEvaluator& jobs) : jobs_(jobs) {}

  std::vector<identify::ReplayOutcome> Replay(const std::vector<identify::ReplayRequest>& requests) override;
  std::uint64_t replays_run() const override { return jobs_.jobs_run(); }
  std::uint64_t replays_stopped_early() const override { return stopped_early_; }

 private:
  runtime::JobEvaluator& jobs_;
  std::atomic<std::uint64_t> stopped_early_{0};
};

/// The job of one replay: the run's scenario with the request's overrides; with `log`, the scenario logs the
/// simulated JointAngle and MotorTorque of every motor of the run's agent; the loss sets the measured_error term's
/// norm, and a finite `stop_above` (degrees) becomes its bound. Not `record` (a field of the job).
v1::Job MakeReplayJob(const identify::ReplayRequest& request);

/// A simulated log (the CSV the worker returns) as columns: path → values per row. Throws InputError naming
/// `source` when it has no "# columns:" line.
std::vector<std::pair<std::string, std::vector<double>>> ParseLogColumns(const std::string& csv,
                                                                         const std::string& source);

}  // namespace orcs::gap
