// Two fitted models compared on orcs's probe motions (probe_motion.h): the motion on which their predicted angles
// differ most is the one to record when the held-out runs cannot choose between them — two effects that tie
// (docs/gap.md, "When two effects explain the data"), or two values of a parameter the fit runs leave open
// ("Parameters the fit runs leave open").
#pragma once

#include <string>
#include <vector>

#include "model/identify/replay.h"
#include "model/identify/replay_evaluator.h"

namespace orcs::identify {

/// The probe motion on which two fitted models differ most.
struct TellApart {
  std::string probe;        ///< ProbeMotion::name; "" = none was tried
  std::string motor;        ///< the motor it moves
  std::string description;  ///< what it does
  std::string shows;        ///< what it shows
  double difference = 0.0;  ///< RMS difference of the two models' angles of `motor` on it, degrees
  double noise = 0.0;       ///< the better model's held-out RMS, degrees: the noise as the best model leaves it
};

/// Every probe motion of `motor`, replayed under `first` and `second` (applied after `model`; noise off, as
/// replays are); the one where their angles differ most. `fit`'s first run lends the probes its servo inputs.
/// `noise` is copied into the result.
TellApart CompareOnProbes(ReplayEvaluator& replays, const Rig& rig, const std::vector<ValueAssignment>& model,
                          const std::vector<ReplayRun>& fit, const std::string& motor,
                          const std::vector<Override>& first, const std::vector<Override>& second, double noise);

}  // namespace orcs::identify
