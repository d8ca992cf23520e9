#include "worker/played_records.h"

#include <algorithm>
#include <iostream>

#include "model/control/keyframe_record.h"
#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {
namespace {

std::string AgentNames(scene::Simulation& simulation) {
  std::string names;
  for (int a = 0; a < simulation.agent_count(); ++a) names += (a ? ", " : "") + simulation.agent(a).name();
  return names.empty() ? "none" : names;
}

}  // namespace

std::vector<control::KeyframePlayer> MakePlayers(const std::vector<std::pair<std::string, std::string>>& plays,
                                                 scene::Simulation& simulation, const std::string& program) {
  std::vector<control::KeyframePlayer> players;
  std::vector<std::string> played;
  for (const auto& [agent, file] : plays) {
    const int index = simulation.FindAgent(agent);
    if (index < 0) {
      throw InputError("-play", 0, "unknown agent " + text::Quote(agent) + " (agents: " + AgentNames(simulation) + ")");
    }
    if (std::find(played.begin(), played.end(), agent) != played.end()) {
      throw InputError("-play", 0, "agent " + text::Quote(agent) + " is given a second record; one record per agent");
    }
    played.push_back(agent);
    aseries::ASeriesAgent& target = simulation.agent(index);
    control::KeyframeRecord record = control::ReadKeyframeRecord(file, target.motor_count());
    if (record.layout_detected && record.layout == control::KeyframeLayout::kNormalised) {
      std::cerr << program << ": " << file << ": every value lies within -1...1 and no '# layout:' line says "
                << "otherwise: read as the older normalised layout\n";
    }
    players.emplace_back(std::move(record), agent, target.motor_names(), simulation.repository());
    for (const std::string& warning : players.back().warnings()) std::cerr << program << ": " << warning << "\n";
  }
  return players;
}

}  // namespace orcs
