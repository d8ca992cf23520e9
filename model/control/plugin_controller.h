// A controller from a plug-in on the worker (model/script/plugin_api.h, docs/extending.md "Plug-ins"):
//   {"type": "plugin", "plugin": "example/hold_pose", "genome_length": N, "params": {...}}
#pragma once

#include <memory>
#include <vector>

#include "model/control/controller.h"
#include "model/core/json_node.h"
#include "model/script/plugin_registry.h"
#include "model/script/plugin_view.h"

namespace orcs::control {

class PluginController : public Controller {
 public:
  /// The component `node` names, made by its factory with `genome`. Throws PluginMissing when `plugins` (may be
  /// null) lacks it, InputError when its factory refuses the params or the genome.
  PluginController(const JsonNode& node, const std::vector<double>& genome, scene::Simulation& simulation,
                   int agent_index, const script::PluginRegistry* plugins);

  void Reset() override { controller_->Reset(view_); }
  void Update(double time_seconds) override { controller_->Update(view_, view_, time_seconds); }

 private:
  script::PluginView view_;
  std::unique_ptr<plugin::Controller> controller_;
};

}  // namespace orcs::control
