// The original's -play AGENT RECORD, shared by orcs-sim and orcs-osp (so it lives beside both, not in either's
// folder: worker/sim/ uses worker/osp/, never the other way): one keyframe player per agent, driven by
// simulated time (docs/formats.md, "Keyframe records").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "model/control/keyframe_player.h"
#include "model/scene/simulation.h"

namespace orcs {

/// One player per (agent, record file) of `plays`, for the agents of the built `simulation`. Throws InputError
/// naming -play for an unknown agent, a second record for one agent, or a record that cannot be read. Notes
/// (a record read in the older normalised layout, clamped inputs) go to stderr prefixed by `program`.
std::vector<control::KeyframePlayer> MakePlayers(const std::vector<std::pair<std::string, std::string>>& plays,
                                                 scene::Simulation& simulation, const std::string& program);

}  // namespace orcs
