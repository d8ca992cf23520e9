#include "model/fitness/fitness_function.h"

#include <set>

#include "model/core/error.h"
#include "model/core/text.h"
#include "model/fitness/plugin_term.h"
#include "model/script/script_spec.h"

namespace orcs::fitness {
namespace {

std::vector<std::pair<std::string, double>> NamesAndWeights(const JsonNode& fitness) {
  fitness.ExpectOnly({"terms", "aggregate", "quantile"});
  std::vector<std::pair<std::string, double>> out;
  std::set<std::string> seen;
  const std::vector<JsonNode> terms = fitness.At("terms").Elements();
  if (terms.empty()) fitness.At("terms").Fail("at least one term");
  for (const JsonNode& term : terms) {
    const std::string type = term.At("type").String(kFitnessTermTypes);
    const std::string name = term.StringOr("name", type, "a term name");
    if (!seen.insert(name).second) {
      term.Fail("a name unique among the terms (set \"name\")", text::Quote(name) + " again");
    }
    out.emplace_back(name, term.NumberOr("weight", 1.0, "a number"));
    if (type == "script") {  // its keys, and its syntax, before any world is built
      term.ExpectOnly({"type", "name", "weight", "script", "params", "limits"});
      script::ParseScriptSpec(term);
    }
    if (type == "plugin") {  // its form; whether a worker has it, only the worker knows
      term.ExpectOnly({"type", "name", "weight", "plugin", "params"});
      script::PluginNameOf(term);
      script::PluginParamsOf(term);
    }
  }
  return out;
}

}  // namespace

FitnessFunction::FitnessFunction(const nlohmann::json& fitness, const scene::Simulation& simulation, int agent_index,
                                 const std::string& source, const script::PluginRegistry* plugins) {
  const JsonNode node(fitness, "fitness", source);
  const std::vector<std::pair<std::string, double>> names = NamesAndWeights(node);
  const std::vector<JsonNode> terms = node.At("terms").Elements();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    entries_.push_back({names[i].first, names[i].second, MakeFitnessTerm(terms[i], simulation, agent_index, plugins)});
  }
}

void FitnessFunction::Start(const scene::Simulation& simulation) {
  for (Entry& entry : entries_) entry.term->Start(simulation);
}

void FitnessFunction::Sample(const scene::Simulation& simulation, double dt) {
  for (Entry& entry : entries_) entry.term->Sample(simulation, dt);
}

std::vector<std::pair<std::string, double>> FitnessFunction::terms() const {
  std::vector<std::pair<std::string, double>> out;
  for (const Entry& entry : entries_) out.emplace_back(entry.name, entry.term->value());
  return out;
}

double FitnessFunction::fitness() const {
  double sum = 0.0;
  for (const Entry& entry : entries_) sum += entry.weight * entry.term->value();
  return sum;
}

bool FitnessFunction::finished() const {
  for (const Entry& entry : entries_) {
    if (entry.term->finished()) return true;
  }
  return false;
}

void CheckFitness(const nlohmann::json& fitness, const std::string& source) {
  NamesAndWeights(JsonNode(fitness, "fitness", source));
}

}  // namespace orcs::fitness
