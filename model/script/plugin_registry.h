// The plug-in components a worker has (model/script/plugin_api.h): "<plug-in>/<component>" → factory. Filled by
// orcs-worker's loader (worker/job/plugin_loader.h) before any job runs; read by the evaluation through
// EvaluationRequest::plugins. No global state: each process holds its own.
#pragma once

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/core/json_node.h"
#include "model/script/plugin_api.h"

namespace orcs::script {

/// A job names a plug-in component this process does not have.
class PluginMissing : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class PluginRegistry : public plugin::Registrar {
 public:
  /// Components registered from now on belong to plug-in `name` (the library's name, "example").
  void BeginPlugin(const std::string& name);

  void AddFitnessTerm(const std::string& component, plugin::FitnessTermFactory factory) override;
  void AddController(const std::string& component, plugin::ControllerFactory factory) override;
  void AddMotorModel(const std::string& component, plugin::MotorModelFactory factory) override;

  /// The factory of "<plug-in>/<component>"; throws PluginMissing naming it and what this process has.
  const plugin::FitnessTermFactory& FitnessTerm(const std::string& name) const;
  const plugin::ControllerFactory& Controller(const std::string& name) const;
  const plugin::MotorModelFactory& MotorModel(const std::string& name) const;

  /// Every component, "<plug-in>/<component>", sorted.
  std::vector<std::string> components() const;

 private:
  [[noreturn]] void Missing(const std::string& name, const char* kind) const;
  std::string plugin_;
  std::map<std::string, plugin::FitnessTermFactory> terms_;
  std::map<std::string, plugin::ControllerFactory> controllers_;
  std::map<std::string, plugin::MotorModelFactory> motor_models_;
};

/// The plug-in component a scenario entry names ("plugin": "<plug-in>/<component>"), checked for its form.
std::string PluginNameOf(const JsonNode& entry);
/// The entry's "params" as JSON text ("{}" when absent), checked to be an object.
std::string PluginParamsOf(const JsonNode& entry);

}  // namespace orcs::script
