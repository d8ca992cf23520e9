// A discrete-time recurrent neural network of additive neurons (docs/scenarios.md, "network"), the controller
// the original's evolution experiments used. Each step:
//   1. every input neuron's output is its bound sensor value, normalised as the agent's values are (JointAngle
//      ±150° → ±1, AccelAxis ±16.07 m/s² → ±1; values without a normalised form are used raw);
//   2. every other neuron computes a_i = bias_i + Σ_j w_ij · o_j from the outputs o_j as they are after step 1
//      (inputs of now, the other neurons of the previous step), then o_i = f(a_i), all at once;
//   3. every output binding writes its neuron's output to the bound input value as a normalised value
//      (DesiredAngle −1…1 ↔ ±150°, DesiredTorque 0…1 ↔ −1…1), clamped to the normalised range.
// Outputs start at 0 after Reset.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/control/controller.h"
#include "model/core/json_node.h"
#include "model/core/value.h"
#include "model/core/variable_repository.h"

namespace orcs::control {

enum class Transfer { kTanh, kSigmoid, kLinear };

/// The network as a description: neurons, synapses, bindings. Parameters that are not given (null in the
/// scenario) are genome slots: every missing bias in neuron order, then every missing weight in synapse order.
struct NetworkDescription {
  struct Neuron {
    std::string name;                ///< unique
    bool input = false;              ///< true: output = the bound sensor value (no bias, no transfer)
    std::string value;               ///< input neurons: the bound repository path
    double bias = 0.0;               ///< additive bias
    bool bias_from_genome = false;   ///< the bias is a genome slot
    Transfer transfer = Transfer::kTanh;
  };
  struct Synapse {
    int from = -1;                   ///< source neuron index
    int to = -1;                     ///< target neuron index (not an input neuron)
    double weight = 0.0;
    bool weight_from_genome = false;  ///< the weight is a genome slot
  };
  struct Output {
    int neuron = -1;                 ///< neuron index
    std::string value;               ///< the bound repository path (an agent input)
  };
  std::vector<Neuron> neurons;
  std::vector<Synapse> synapses;
  std::vector<Output> outputs;

  /// Number of genome slots.
  int genome_length() const;
  /// A copy with the genome's numbers in the slots. Throws InputError (source, "genome") for a wrong length.
  NetworkDescription WithGenome(const std::vector<double>& genome, const std::string& source) const;
};

/// Parses a network: {"transfer", "inputs": [{"name", "value"}], "neurons": [{"name", "bias", "transfer"}],
/// "synapses": [{"from", "to", "weight"}], "outputs": [{"neuron", "value"}]} (+ "type": "network"). Values
/// are agent-relative ("Right/Knee/JointAngle") unless they start with '/'; `agent` completes them to
/// /Sim/<agent>/.... A bias or weight of null (or left out) is a genome slot when `allow_slots`, an error
/// otherwise. Throws InputError naming the field.
NetworkDescription ParseNetwork(const JsonNode& node, const std::string& agent, bool allow_slots);

class NeuralNetwork : public Controller {
 public:
  /// Binds the network's values; throws InputError naming the path when one is not in `values`.
  NeuralNetwork(NetworkDescription description, VariableRepository& values, const std::string& source);

  void Reset() override;
  void Update(double time_seconds) override;

  const std::vector<double>& outputs() const { return outputs_; }  ///< every neuron's output, neuron order

 private:
  NetworkDescription description_;
  std::vector<const Value*> input_values_;  // per neuron: the bound sensor value for inputs, else nullptr
  std::vector<Value*> output_values_;       // per output binding
  std::vector<double> outputs_;             // o_j, neuron order
  std::vector<double> activations_;         // scratch: a_i
};

}  // namespace orcs::control
