// A scenario's fitness (docs/scenarios.md, "fitness"): named, weighted terms; fitness = Σ weight · term.
//   "fitness": {"terms": [{"type": "distance", "name": "forward", "weight": 1, ...}, ...],
//               "aggregate": "mean" | "min" | "max" | "quantile", "quantile": 0.25}
// (the aggregate over parameter sets is read by scene::ParseScenario).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "model/fitness/fitness_terms.h"

namespace orcs::fitness {

class FitnessFunction {
 public:
  /// Builds the terms for agent `agent_index` of the built `simulation`. Throws InputError naming the field.
  /// `plugins`: the process's plug-in components for "plugin" terms (null: none).
  FitnessFunction(const nlohmann::json& fitness, const scene::Simulation& simulation, int agent_index,
                  const std::string& source, const script::PluginRegistry* plugins = nullptr);

  void Start(const scene::Simulation& simulation);
  void Sample(const scene::Simulation& simulation, double dt);

  /// Each term's name and value, in the scenario's order.
  std::vector<std::pair<std::string, double>> terms() const;
  /// Σ weight · value.
  double fitness() const;
  /// Whether a term has finished (FitnessTerm::finished): the run may stop.
  bool finished() const;

 private:
  struct Entry {
    std::string name;
    double weight = 1.0;
    std::unique_ptr<FitnessTerm> term;
  };
  std::vector<Entry> entries_;
};

/// Checks a fitness section's shape (keys, types, names) without a world. Throws InputError naming the field.
void CheckFitness(const nlohmann::json& fitness, const std::string& source);

}  // namespace orcs::fitness
