#include "model/script/plugin_registry.h"

#include "model/core/error.h"

namespace orcs::script {

void PluginRegistry::BeginPlugin(const std::string& name) { plugin_ = name; }

void PluginRegistry::AddFitnessTerm(const std::string& component, plugin::FitnessTermFactory factory) {
  terms_[plugin_ + "/" + component] = std::move(factory);
}

void PluginRegistry::AddController(const std::string& component, plugin::ControllerFactory factory) {
  controllers_[plugin_ + "/" + component] = std::move(factory);
}

void PluginRegistry::AddMotorModel(const std::string& component, plugin::MotorModelFactory factory) {
  motor_models_[plugin_ + "/" + component] = std::move(factory);
}

const plugin::MotorModelFactory& PluginRegistry::MotorModel(const std::string& name) const {
  const auto found = motor_models_.find(name);
  if (found == motor_models_.end()) Missing(name, "motor model");
  return found->second;
}

const plugin::FitnessTermFactory& PluginRegistry::FitnessTerm(const std::string& name) const {
  const auto found = terms_.find(name);
  if (found == terms_.end()) Missing(name, "fitness term");
  return found->second;
}

const plugin::ControllerFactory& PluginRegistry::Controller(const std::string& name) const {
  const auto found = controllers_.find(name);
  if (found == controllers_.end()) Missing(name, "controller");
  return found->second;
}

std::vector<std::string> PluginRegistry::components() const {
  std::vector<std::string> names;
  for (const auto& [name, factory] : terms_) names.push_back(name);
  for (const auto& [name, factory] : controllers_) names.push_back(name);
  for (const auto& [name, factory] : motor_models_) names.push_back(name);
  std::sort(names.begin(), names.end());
  return names;
}

void PluginRegistry::Missing(const std::string& name, const char* kind) const {
  std::string has;
  for (const std::string& component : components()) has += (has.empty() ? "" : ", ") + component;
  throw PluginMissing("plug-in " + std::string(kind) + " '" + name + "' is not installed on this worker (it has " +
                      (has.empty() ? "no plug-ins" : has) + "); start orcs-worker with --plugins DIR holding lib" +
                      name.substr(0, name.find('/')) + ".so");
}

std::string PluginNameOf(const JsonNode& entry) {
  const JsonNode node = entry.At("plugin");
  const std::string name = node.String("\"<plug-in>/<component>\", e.g. \"example/mean_height\"");
  const std::size_t slash = name.find('/');
  if (slash == 0 || slash == std::string::npos || slash + 1 == name.size()) {
    node.Fail("\"<plug-in>/<component>\", e.g. \"example/mean_height\"");
  }
  return name;
}

std::string PluginParamsOf(const JsonNode& entry) {
  if (!entry.Has("params")) return "{}";
  const JsonNode params = entry.At("params");
  if (!params.value().is_object()) params.Fail("an object of the plug-in's parameters");
  return params.value().dump();
}

}  // namespace orcs::script
