// A fitness term from a plug-in on the worker (model/script/plugin_api.h, docs/extending.md "Plug-ins"):
//   {"type": "plugin", "plugin": "example/mean_height", "name": "...", "weight": 1, "params": {...}}
#pragma once

#include <memory>
#include <string>

#include "model/core/json_node.h"
#include "model/fitness/fitness_terms.h"
#include "model/script/plugin_registry.h"
#include "model/script/plugin_view.h"

namespace orcs::fitness {

class PluginTerm : public FitnessTerm {
 public:
  /// The component `entry` names, made by its factory. Throws PluginMissing when `plugins` (may be null) lacks it,
  /// InputError when its factory refuses the params.
  PluginTerm(const JsonNode& entry, const scene::Simulation& simulation, int agent_index,
             const script::PluginRegistry* plugins);

  void Start(const scene::Simulation&) override { term_->Start(view_); }
  void Sample(const scene::Simulation&, double dt) override { term_->Sample(view_, dt); }
  double value() const override { return term_->Value(); }
  bool finished() const override { return term_->Finished(); }

 private:
  script::PluginView view_;
  std::unique_ptr<plugin::FitnessTerm> term_;
};

}  // namespace orcs::fitness
