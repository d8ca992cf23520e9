#include "clients/evolve/evolution_settings.h"

#include <array>
#include <utility>

#include "model/control/controller_factory.h"
#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/random_stream.h"
#include "model/evaluation/evaluation.h"

namespace orcs::evolve {
namespace {

constexpr std::array<std::pair<Algorithm, const char*>, 5> kAlgorithms = {{{Algorithm::kCmaes, "cmaes"},
                                                                           {Algorithm::kXnes, "xnes"},
                                                                           {Algorithm::kSga, "sga"},
                                                                           {Algorithm::kDe, "de"},
                                                                           {Algorithm::kPsoGen, "pso_gen"}}};

std::string AlgorithmList() { return "\"cmaes\", \"xnes\", \"sga\", \"de\" or \"pso_gen\""; }

bool ParseAlgorithm(const std::string& name, Algorithm& algorithm) {
  for (const auto& [value, text] : kAlgorithms) {
    if (name == text) {
      algorithm = value;
      return true;
    }
  }
  return false;
}

GeneBounds ReadRange(const JsonNode& node) {
  const std::vector<double> pair = node.Numbers("[low, high]");
  if (pair.size() != 2 || !(pair[0] < pair[1])) node.Fail("[low, high] with low < high");
  return {pair[0], pair[1]};
}

// "bounds": [low, high] for every gene, or [[low, high], ...] with one range per gene.
std::vector<GeneBounds> ReadBounds(const JsonNode& node, std::size_t genes) {
  if (!node.value().is_array() || node.value().empty()) node.Fail("[low, high] or one [low, high] per gene");
  if (!node.value().front().is_array()) return std::vector<GeneBounds>(genes, ReadRange(node));
  std::vector<GeneBounds> bounds;
  for (const JsonNode& gene : node.Elements()) bounds.push_back(ReadRange(gene));
  if (bounds.size() != genes) {
    node.Fail("one [low, high] per gene (" + std::to_string(genes) + ")", std::to_string(bounds.size()) + " ranges");
  }
  return bounds;
}

// The number of genes: the length of the flat genome the scenario's controller takes.
std::size_t GenomeLength(const runtime::ScenarioInput& input) {
  const control::ControlTarget target = evaluation::ControlTargetOf(input.scenario);
  const int length = control::CheckController(input.scenario.controller, target, input.path);
  if (length <= 0) {
    throw InputError(input.path +
                     ": field 'controller' has no free genes to evolve (a keyframe player, or a "
                     "network without null weights or biases)");
  }
  return static_cast<std::size_t>(length);
}

}  // namespace

std::uint64_t GenerationSeed(const EvolutionSettings& settings, int generation) {
  if (!settings.fresh_sets) return settings.seed;
  RandomStream stream(settings.seed, "evolve-generation-sets", static_cast<std::uint64_t>(generation));
  return stream.NextU64();
}

namespace {

void ReadSection(const JsonNode& section, EvolutionSettings& settings) {
  section.ExpectOnly({"bounds", "algorithm", "population", "generations", "seed", "sigma", "validate", "fresh_sets"});
  if (section.Has("algorithm")) {
    const JsonNode node = section.At("algorithm");
    if (!ParseAlgorithm(node.String("an algorithm name"), settings.algorithm)) node.Fail(AlgorithmList());
  }
  if (section.Has("population")) settings.population = section.At("population").Integer("a population size");
  if (section.Has("generations")) {
    const JsonNode node = section.At("generations");
    settings.generations = node.Integer("a number of generations ≥ 0");
    if (settings.generations < 0) node.Fail("a number of generations ≥ 0");
  }
  if (section.Has("seed")) settings.seed = section.At("seed").Unsigned("a seed ≥ 0");
  if (section.Has("sigma")) {
    const JsonNode node = section.At("sigma");
    settings.sigma = node.Number("a step > 0 and ≤ 1, in units of each gene's range");
    if (!(settings.sigma > 0.0 && settings.sigma <= 1.0))
      node.Fail("a step > 0 and ≤ 1, in units of each gene's range");
  }
  if (section.Has("fresh_sets")) settings.fresh_sets = section.At("fresh_sets").Bool("true or false");
  if (section.Has("validate")) {
    const JsonNode node = section.At("validate");
    settings.validate = node.Integer("a number of seeds ≥ 0");
    if (settings.validate < 0) node.Fail("a number of seeds ≥ 0");
  }
}

void ApplyOverrides(const EvolutionOverrides& overrides, EvolutionSettings& settings) {
  if (!overrides.algorithm.empty() && !ParseAlgorithm(overrides.algorithm, settings.algorithm)) {
    throw InputError("--algorithm '" + overrides.algorithm + "': expected " + AlgorithmList());
  }
  if (overrides.population != 0) settings.population = overrides.population;
  if (overrides.generations >= 0) settings.generations = overrides.generations;
  if (overrides.seed >= 0) settings.seed = static_cast<std::uint64_t>(overrides.seed);
  if (overrides.validate >= 0) settings.validate = overrides.validate;
  if (overrides.fresh_sets) settings.fresh_sets = true;
}

void CheckPopulation(const runtime::ScenarioInput& input, const EvolutionSettings& settings) {
  const int minimum = MinimumPopulation(settings.algorithm);
  if (settings.population < minimum || settings.population > 100000) {
    throw InputError(input.path + ": population " + std::to_string(settings.population) + " (field " +
                     "'evolution.population' or --population): " + AlgorithmName(settings.algorithm) +
                     " needs at least " + std::to_string(minimum) + " genomes per generation (at most 100000)");
  }
}

// The scenario's "genome" becomes the first individual; it must be flat and inside the bounds.
std::vector<double> ReadStart(const runtime::ScenarioInput& input, const std::vector<GeneBounds>& bounds) {
  const nlohmann::json& genome = input.scenario.genome;
  if (genome.is_null()) return {};
  const JsonNode node(genome, "genome", input.path);
  const std::vector<double> start = node.Numbers("a flat array of numbers (orcs-batch evolve evolves flat genomes)");
  if (start.size() != bounds.size()) {
    node.Fail(std::to_string(bounds.size()) + " genes", std::to_string(start.size()) + " numbers");
  }
  for (std::size_t i = 0; i < start.size(); ++i) {
    if (start[i] < bounds[i].low || start[i] > bounds[i].high) {
      throw InputError(input.path + ": field 'genome[" + std::to_string(i) + "]' = " + std::to_string(start[i]) +
                       " is outside its bounds [" + std::to_string(bounds[i].low) + ", " +
                       std::to_string(bounds[i].high) + "] (field 'evolution.bounds')");
    }
  }
  return start;
}

}  // namespace

std::string AlgorithmName(Algorithm algorithm) {
  for (const auto& [value, text] : kAlgorithms) {
    if (value == algorithm) return text;
  }
  return "?";
}

int MinimumPopulation(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kCmaes:
    case Algorithm::kXnes:
    case Algorithm::kDe:
      return 5;  // pagmo2's own check (xNES's message asks for 5 though its check lets 4 pass)
    case Algorithm::kSga:
    case Algorithm::kPsoGen:
      return 2;  // SGA's crossover pairs; pso_gen crashes with a single particle
  }
  return 2;
}

EvolutionSettings ReadEvolutionSettings(const runtime::ScenarioInput& input, const EvolutionOverrides& overrides) {
  const nlohmann::json& section = input.scenario.evolution;
  if (section.is_null()) {
    throw InputError(input.path +
                     ": no field 'evolution': orcs-batch evolve needs at least its \"bounds\" "
                     "(docs/evolution.md)");
  }
  const JsonNode node(section, "evolution", input.path);
  EvolutionSettings settings;
  ReadSection(node, settings);
  if (!node.Has("bounds")) node.Fail("an object with \"bounds\"", "no \"bounds\"");
  settings.bounds = ReadBounds(node.At("bounds"), GenomeLength(input));
  settings.start = ReadStart(input, settings.bounds);
  ApplyOverrides(overrides, settings);
  CheckPopulation(input, settings);
  return settings;
}

}  // namespace orcs::evolve
