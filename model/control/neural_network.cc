#include "model/control/neural_network.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "model/aseries/value_range.h"
#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::control {
namespace {

Transfer TransferOf(const JsonNode& node) {
  const std::string name = node.String("\"tanh\", \"sigmoid\" or \"linear\"");
  if (name == "tanh") return Transfer::kTanh;
  if (name == "sigmoid") return Transfer::kSigmoid;
  if (name == "linear") return Transfer::kLinear;
  node.Fail("\"tanh\", \"sigmoid\" or \"linear\"");
}

double Apply(Transfer transfer, double activation) {
  switch (transfer) {
    case Transfer::kTanh: return std::tanh(activation);
    case Transfer::kSigmoid: return 1.0 / (1.0 + std::exp(-activation));
    case Transfer::kLinear: return activation;
  }
  return activation;
}

std::string AgentPath(const std::string& value, const std::string& agent) {
  return !value.empty() && value[0] == '/' ? value : "/Sim/" + agent + "/" + value;
}

// A number, or a genome slot (null or missing) when slots are allowed.
double Parameter(const JsonNode& owner, const char* key, bool allow_slots, bool& from_genome) {
  from_genome = !owner.Has(key) || owner.At(key).value().is_null();
  if (from_genome && !allow_slots) {
    owner.Fail(std::string("a number in '") + key + "' (a full network has no genome slots)");
  }
  return from_genome ? 0.0 : owner.At(key).Number("a number or null (a genome slot)");
}

}  // namespace

int NetworkDescription::genome_length() const {
  int count = 0;
  for (const Neuron& neuron : neurons) count += neuron.bias_from_genome ? 1 : 0;
  for (const Synapse& synapse : synapses) count += synapse.weight_from_genome ? 1 : 0;
  return count;
}

NetworkDescription NetworkDescription::WithGenome(const std::vector<double>& genome, const std::string& source) const {
  if (static_cast<int>(genome.size()) != genome_length()) {
    throw InputError(source, 0,
                     "genome expected " + std::to_string(genome_length()) + " numbers (the network's free biases and "
                     "weights), found " + std::to_string(genome.size()));
  }
  NetworkDescription filled = *this;
  std::size_t next = 0;
  for (Neuron& neuron : filled.neurons) {
    if (neuron.bias_from_genome) neuron.bias = genome[next++];
  }
  for (Synapse& synapse : filled.synapses) {
    if (synapse.weight_from_genome) synapse.weight = genome[next++];
  }
  return filled;
}

NetworkDescription ParseNetwork(const JsonNode& node, const std::string& agent, bool allow_slots) {
  node.ExpectOnly({"type", "transfer", "inputs", "neurons", "synapses", "outputs"});
  const Transfer default_transfer = node.Has("transfer") ? TransferOf(node.At("transfer")) : Transfer::kTanh;
  NetworkDescription network;
  std::unordered_map<std::string, int> index;
  const auto add = [&](NetworkDescription::Neuron neuron, const JsonNode& where) {
    if (neuron.name.empty()) where.At("name").Fail("a non-empty name");
    if (!index.emplace(neuron.name, static_cast<int>(network.neurons.size())).second) {
      where.At("name").Fail("a name unique among inputs and neurons", text::Quote(neuron.name) + " again");
    }
    network.neurons.push_back(std::move(neuron));
  };
  if (node.Has("inputs")) {
    for (const JsonNode& input : node.At("inputs").Elements()) {
      input.ExpectOnly({"name", "value"});
      NetworkDescription::Neuron neuron;
      neuron.name = input.At("name").String("a neuron name");
      neuron.input = true;
      neuron.value = AgentPath(input.At("value").String("a sensor value like \"Right/Knee/JointAngle\""), agent);
      add(std::move(neuron), input);
    }
  }
  for (const JsonNode& element : node.At("neurons").Elements()) {
    element.ExpectOnly({"name", "bias", "transfer"});
    NetworkDescription::Neuron neuron;
    neuron.name = element.At("name").String("a neuron name");
    neuron.bias = Parameter(element, "bias", allow_slots, neuron.bias_from_genome);
    neuron.transfer = element.Has("transfer") ? TransferOf(element.At("transfer")) : default_transfer;
    add(std::move(neuron), element);
  }
  const auto neuron_of = [&](const JsonNode& name) {
    const auto it = index.find(name.String("a neuron name"));
    if (it == index.end()) name.Fail("the name of an input or neuron", text::Quote(name.String("")));
    return it->second;
  };
  if (node.Has("synapses")) {
    for (const JsonNode& element : node.At("synapses").Elements()) {
      element.ExpectOnly({"from", "to", "weight"});
      NetworkDescription::Synapse synapse;
      synapse.from = neuron_of(element.At("from"));
      synapse.to = neuron_of(element.At("to"));
      if (network.neurons[synapse.to].input) element.At("to").Fail("a neuron that is not an input");
      synapse.weight = Parameter(element, "weight", allow_slots, synapse.weight_from_genome);
      network.synapses.push_back(synapse);
    }
  }
  for (const JsonNode& element : node.At("outputs").Elements()) {
    element.ExpectOnly({"neuron", "value"});
    NetworkDescription::Output output;
    output.neuron = neuron_of(element.At("neuron"));
    output.value = AgentPath(element.At("value").String("a motor input like \"Right/Knee/DesiredAngle\""), agent);
    network.outputs.push_back(output);
  }
  return network;
}

NeuralNetwork::NeuralNetwork(NetworkDescription description, VariableRepository& values, const std::string& source)
    : description_(std::move(description)) {
  const auto bind = [&](const std::string& path) -> Value& {
    Value* value = values.Find(path);
    if (value == nullptr) throw InputError(source, 0, "controller: unknown repository value " + text::Quote(path));
    if (value->type() != ValueType::kDouble) {
      throw InputError(source, 0, "controller: " + text::Quote(path) + " is not a number value");
    }
    return *value;
  };
  for (const NetworkDescription::Neuron& neuron : description_.neurons) {
    input_values_.push_back(neuron.input ? &bind(neuron.value) : nullptr);
  }
  for (const NetworkDescription::Output& output : description_.outputs) output_values_.push_back(&bind(output.value));
  outputs_.assign(description_.neurons.size(), 0.0);
  activations_.assign(description_.neurons.size(), 0.0);
}

void NeuralNetwork::Reset() { std::fill(outputs_.begin(), outputs_.end(), 0.0); }

void NeuralNetwork::Update(double /*time_seconds*/) {
  const std::size_t count = description_.neurons.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Value* sensor = input_values_[i];
    if (sensor == nullptr) continue;
    const aseries::ValueRange* range = aseries::InterfaceRangeOf(description_.neurons[i].value);
    outputs_[i] = range != nullptr ? range->ToNormalised(sensor->as_double()) : sensor->as_double();
  }
  for (std::size_t i = 0; i < count; ++i) activations_[i] = description_.neurons[i].bias;
  for (const NetworkDescription::Synapse& synapse : description_.synapses) {
    activations_[synapse.to] += synapse.weight * outputs_[synapse.from];
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!description_.neurons[i].input) outputs_[i] = Apply(description_.neurons[i].transfer, activations_[i]);
  }
  for (std::size_t k = 0; k < description_.outputs.size(); ++k) {
    const NetworkDescription::Output& output = description_.outputs[k];
    const double normalised = outputs_[output.neuron];
    const aseries::ValueRange* range = aseries::InterfaceRangeOf(output.value);
    output_values_[k]->Set(range != nullptr ? range->ToRaw(normalised) : normalised);
  }
}

}  // namespace orcs::control
