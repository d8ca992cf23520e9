#include "model/control/plugin_controller.h"

#include <stdexcept>

#include "model/core/error.h"

namespace orcs::control {
namespace {

std::unique_ptr<plugin::Controller> MakePluginController(const JsonNode& node, const std::vector<double>& genome,
                                                         const script::PluginRegistry* plugins) {
  const std::string name = script::PluginNameOf(node);
  const std::string params = script::PluginParamsOf(node);
  if (plugins == nullptr) throw script::PluginMissing("plug-in controller '" + name + "': this process loads no plug-ins");
  try {
    std::unique_ptr<plugin::Controller> controller = plugins->Controller(name)(params, genome);
    if (controller == nullptr) throw std::invalid_argument("its factory made nothing");
    return controller;
  } catch (const std::invalid_argument& error) {
    (node.Has("params") ? node.At("params") : node).Fail("params and a genome plug-in '" + name + "' accepts", error.what());
  }
}

}  // namespace

PluginController::PluginController(const JsonNode& node, const std::vector<double>& genome,
                                   scene::Simulation& simulation, int agent_index,
                                   const script::PluginRegistry* plugins)
    : view_(simulation, agent_index, &simulation.repository()),
      controller_(MakePluginController(node, genome, plugins)) {}

}  // namespace orcs::control
