// The seam between the gap workflow's analysis and whatever runs its replays: the fits and the diagnosis ask a
// ReplayEvaluator to replay measured runs under candidate models, so that the same analysis runs through a broker
// (orcs-gap's BrokerReplays, clients/gap/broker_replays.h) and on a cheap analytic stand-in in unit tests.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "model/identify/replay.h"

namespace orcs::identify {

/// How a fit weighs the angle errors (orcs-gap --loss; docs/gap.md, "How a fit works").
enum class Loss {
  kSquared,   ///< the mean squared error, deg²: least squares, the default
  kAbsolute,  ///< the mean absolute error, deg: BAM's, less pulled by a few large errors (a snag, a stuck segment)
};

/// One replay to run: a measured run under the model with `overrides` applied after it.
struct ReplayRequest {
  const ReplayRun* run = nullptr;   ///< the run and its rig (owned by the caller)
  std::vector<Override> overrides;  ///< repository path → value text, applied in order
  bool log = false;                 ///< return the simulated JointAngle and MotorTorque of every motor
  bool record = false;              ///< return the replay's recording (docs/recording.md)
  /// The replay may stop as soon as its error can no longer end at or below this (degrees; measured_error's
  /// "stop_above"): its error is then a lower bound above it. +∞ = run to the end.
  double stop_above = std::numeric_limits<double>::infinity();
  Loss loss = Loss::kSquared;  ///< the error's norm: RMS (kSquared) or mean absolute (kAbsolute)
};

/// What one replay gave.
struct ReplayOutcome {
  bool ok = false;  ///< the replay ran to its end (false: unstable physics, a timeout, a refused model)
  /// The joint-angle error against the run, degrees: RMS, or the mean absolute error with Loss::kAbsolute.
  double error = std::numeric_limits<double>::quiet_NaN();
  /// With ReplayRequest::log: the simulated columns by repository path ("/Sim/<agent>/<motor>/JointAngle"), one
  /// value per measured row; empty when the replay failed.
  std::vector<std::pair<std::string, std::vector<double>>> columns;
  std::string recording;  ///< with ReplayRequest::record: the recording's bytes ("" when none was made)
  bool stopped_early = false;  ///< stopped at ReplayRequest::stop_above: error is a lower bound, above it
};

class ReplayEvaluator {
 public:
  virtual ~ReplayEvaluator() = default;

  /// Runs every request and returns the outcomes in the same order. Thread-safe: several fits call it at once.
  virtual std::vector<ReplayOutcome> Replay(const std::vector<ReplayRequest>& requests) = 0;

  /// Replays run so far.
  virtual std::uint64_t replays_run() const = 0;
  /// Of those, the ones that stopped early (ReplayRequest::stop_above); 0 for an evaluator that never stops.
  virtual std::uint64_t replays_stopped_early() const { return 0; }
};

}  // namespace orcs::identify
