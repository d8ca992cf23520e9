#include "model/fitness/plugin_term.h"

#include "model/core/error.h"

namespace orcs::fitness {

namespace {

std::unique_ptr<plugin::FitnessTerm> MakeTerm(const JsonNode& entry, const script::PluginRegistry* plugins) {
  const std::string name = script::PluginNameOf(entry);
  const std::string params = script::PluginParamsOf(entry);
  if (plugins == nullptr) throw script::PluginMissing("plug-in fitness term '" + name + "': this process loads no plug-ins");
  try {
    std::unique_ptr<plugin::FitnessTerm> term = plugins->FitnessTerm(name)(params);
    if (term == nullptr) throw std::invalid_argument("its factory made nothing");
    return term;
  } catch (const std::invalid_argument& error) {
    (entry.Has("params") ? entry.At("params") : entry).Fail("params plug-in '" + name + "' accepts", error.what());
  }
}

}  // namespace

PluginTerm::PluginTerm(const JsonNode& entry, const scene::Simulation& simulation, int agent_index,
                       const script::PluginRegistry* plugins)
    : view_(simulation, agent_index, nullptr), term_(MakeTerm(entry, plugins)) {}

}  // namespace orcs::fitness
