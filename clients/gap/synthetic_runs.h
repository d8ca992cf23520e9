// `orcs-gap synth` (docs/gap.md, "Data with a hidden effect"): "measured" runs made by the simulation itself —
// a motion played on the rig with hidden values (an effect switched on, mistuned base parameters) and the sensor
// noise of the spec on — written in the native log format, whose header names neither the hidden values nor the
// effect. The workflow is then given only these files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/identify/replay.h"

namespace orcs::gap {

struct SynthOptions {
  std::vector<std::string> motions;  ///< keyframe records (docs/formats.md) to play, one run each
  std::vector<identify::Override> hidden;      ///< values applied after the model: the truth the workflow must find
  std::uint64_t seed = 1;            ///< noise seed of the first run; run k uses seed + k
  double duration = 0.0;             ///< simulated seconds per run; ≤ 0 = each record's last keyframe
  std::string out;                   ///< folder for <motion stem>.csv
  bool accelerometers = false;       ///< log the agent's accelerometer axes too (docs/gap_measured_data.md)
};

/// Writes one run per motion and returns the files written. Throws InputError for unreadable records, unknown
/// paths or values, and when a run does not complete (unstable physics).
std::vector<std::string> WriteSyntheticRuns(const identify::Rig& rig, const std::vector<ValueAssignment>& model,
                                            const SynthOptions& options);

}  // namespace orcs::gap
