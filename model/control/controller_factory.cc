#include "model/control/controller_factory.h"

#include "model/control/keyframe_player.h"
#include "model/control/neural_network.h"
#include "model/control/plugin_controller.h"
#include "model/control/script_controller.h"
#include "model/control/sine_oscillator.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"

namespace orcs::control {
namespace {

using Json = nlohmann::json;

constexpr const char* kControllerTypes = "\"network\", \"oscillator\", \"keyframes\", \"script\" or \"plugin\"";

std::string TypeOf(const JsonNode& node) {
  const std::string type = node.At("type").String(kControllerTypes);
  if (type != "network" && type != "oscillator" && type != "keyframes" && type != "script" && type != "plugin") {
    node.At("type").Fail(kControllerTypes);
  }
  return type;
}

// "genome_length" of a script or plug-in controller: 0 to 100000 genes, 0 when absent.
int GenomeLengthOf(const JsonNode& node) {
  if (!node.Has("genome_length")) return 0;
  const int length = node.At("genome_length").Integer("a number of genes, 0 to 100000");
  if (length < 0 || length > 100000) node.At("genome_length").Fail("a number of genes, 0 to 100000");
  return length;
}

// A script controller's spec (syntax checked) and its genome length.
std::pair<script::ScriptSpec, int> ScriptOf(const JsonNode& node) {
  node.ExpectOnly({"type", "script", "genome_length", "params", "limits"});
  return {script::ParseScriptSpec(node), GenomeLengthOf(node)};
}

// A plug-in controller's form (whether this process has it is not checked here) and its genome length.
int PluginGenomeLength(const JsonNode& node) {
  node.ExpectOnly({"type", "plugin", "genome_length", "params"});
  script::PluginNameOf(node);
  script::PluginParamsOf(node);
  return GenomeLengthOf(node);
}

std::vector<std::string> OscillatorJoints(const JsonNode& node, const ControlTarget& target) {
  node.ExpectOnly({"type", "joints", "torque"});
  std::vector<std::string> joints;
  for (const JsonNode& joint : node.At("joints").Elements()) {
    const std::string name = joint.String("a motor name");
    if (std::find(target.motors.begin(), target.motors.end(), name) == target.motors.end()) {
      joint.Fail("a motor of agent " + text::Quote(target.agent));
    }
    joints.push_back(name);
  }
  if (node.Has("torque")) {
    const double torque = node.At("torque").Number("a raw DesiredTorque −1…1");
    if (torque < -1 || torque > 1) node.At("torque").Fail("a raw DesiredTorque −1…1");
  }
  return joints;
}

KeyframeRecord RecordOf(const JsonNode& node, const ControlTarget& target) {
  node.ExpectOnly({"type", "record"});
  const JsonNode record = node.At("record");
  if (!record.value().is_object()) record.Fail("an inlined record {\"file\", \"text\"} (resolve the scenario first)");
  record.ExpectOnly({"file", "text"});
  return ParseKeyframeRecord(record.At("text").String("the record's text"),
                             record.StringOr("file", node.source() + ": field 'controller.record'", "a file name"),
                             static_cast<int>(target.motors.size()));
}

std::vector<double> FlatGenome(const Json& genome, const std::string& source) {
  const JsonNode node(genome, "genome", source);
  return node.Numbers("genome values");
}

}  // namespace

int CheckController(const Json& controller, const ControlTarget& target, const std::string& source) {
  const JsonNode node(controller, "controller", source);
  const std::string type = TypeOf(node);
  if (type == "network") return ParseNetwork(node, target.agent, true).genome_length();
  if (type == "oscillator") return SineOscillator::kGenesPerJoint * static_cast<int>(OscillatorJoints(node, target).size());
  if (type == "script") return ScriptOf(node).second;
  if (type == "plugin") return PluginGenomeLength(node);
  RecordOf(node, target);
  return 0;
}

void CheckGenome(const Json& controller, const Json& genome, const ControlTarget& target, const std::string& source) {
  const int length = CheckController(controller, target, source);
  const JsonNode genome_node(genome, "genome", source);
  if (genome.is_object()) {
    if (JsonNode(controller, "controller", source).At("type").String("") != "network") {
      genome_node.Fail("an array of numbers (only a network genome may be a full network)");
    }
    ParseNetwork(genome_node, target.agent, false);
    return;
  }
  const std::vector<double> flat = FlatGenome(genome, source);
  if (static_cast<int>(flat.size()) != length) {
    genome_node.Fail(std::to_string(length) + " numbers", "an array of " + std::to_string(flat.size()));
  }
}

std::unique_ptr<Controller> MakeController(const Json& controller, const Json& genome, const ControlTarget& target,
                                           VariableRepository& values, const std::string& source) {
  CheckGenome(controller, genome, target, source);
  const JsonNode node(controller, "controller", source);
  const std::string type = TypeOf(node);
  if (type == "network") {
    NetworkDescription network = genome.is_object()
                                     ? ParseNetwork(JsonNode(genome, "genome", source), target.agent, false)
                                     : ParseNetwork(node, target.agent, true).WithGenome(FlatGenome(genome, source), source);
    return std::make_unique<NeuralNetwork>(std::move(network), values, source);
  }
  if (type == "oscillator") {
    const std::vector<std::string> names = OscillatorJoints(node, target);
    const std::vector<double> genes = FlatGenome(genome, source);
    std::vector<SineJoint> joints;
    for (std::size_t j = 0; j < names.size(); ++j) {
      const double* g = &genes[SineOscillator::kGenesPerJoint * j];
      joints.push_back({names[j], g[0], g[1], g[2], g[3]});
    }
    std::optional<double> torque;
    if (node.Has("torque")) torque = node.At("torque").Number("");
    return std::make_unique<SineOscillator>(std::move(joints), target.agent, torque, values, source);
  }
  if (type == "script" || type == "plugin") node.Fail("a controller of a simulation (made with one)");
  return std::make_unique<KeyframePlayer>(RecordOf(node, target), target.agent, target.motors, values);
}

std::unique_ptr<Controller> MakeController(const Json& controller, const Json& genome, const ControlTarget& target,
                                           scene::Simulation& simulation, int agent_index, const std::string& source,
                                           const script::PluginRegistry* plugins) {
  const JsonNode node(controller, "controller", source);
  const std::string type = TypeOf(node);
  if (type != "script" && type != "plugin") {
    return MakeController(controller, genome, target, simulation.repository(), source);
  }
  CheckGenome(controller, genome, target, source);
  if (type == "plugin") {
    return std::make_unique<PluginController>(node, FlatGenome(genome, source), simulation, agent_index, plugins);
  }
  return std::make_unique<ScriptController>(ScriptOf(node).first, FlatGenome(genome, source), simulation, agent_index);
}

}  // namespace orcs::control
