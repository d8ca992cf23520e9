#include "model/identify/batch_problem.h"

#include "base/demand.h"

#include <algorithm>

namespace orcs::identify {

void GenerationCache::EvaluateRecorded() {
  if (recorded.empty()) return;
  const std::vector<double> objectives = evaluate(recorded);
  ORCS_DEMAND(objectives.size() == recorded.size());
  for (std::size_t i = 0; i < recorded.size(); ++i) known[recorded[i]] = objectives[i];
  recorded.clear();
}

BatchProblem::BatchProblem(std::size_t dimension, std::shared_ptr<GenerationCache> cache)
    : dimension_(dimension), cache_(std::move(cache)) {}

pagmo::vector_double BatchProblem::fitness(const pagmo::vector_double& x) const { return Answer({x}); }

pagmo::vector_double BatchProblem::batch_fitness(const pagmo::vector_double& xs) const {
  std::vector<pagmo::vector_double> vectors;
  for (std::size_t start = 0; start + dimension_ <= xs.size(); start += dimension_) {
    vectors.emplace_back(xs.begin() + static_cast<std::ptrdiff_t>(start),
                         xs.begin() + static_cast<std::ptrdiff_t>(start + dimension_));
  }
  return Answer(vectors);
}

std::pair<pagmo::vector_double, pagmo::vector_double> BatchProblem::get_bounds() const {
  return {pagmo::vector_double(dimension_, 0.0), pagmo::vector_double(dimension_, 1.0)};
}

std::vector<double> BatchProblem::Answer(const std::vector<pagmo::vector_double>& xs) const {
  ORCS_DEMAND_MSG(cache_, "BatchProblem used without a cache (Attach after loading)");
  GenerationCache& cache = *cache_;
  for (const pagmo::vector_double& x : xs) {
    const bool asked = std::find(cache.recorded.begin(), cache.recorded.end(), x) != cache.recorded.end();
    if (cache.known.count(x) == 0 && !asked) cache.recorded.push_back(x);
  }
  if (cache.mode == GenerationCache::Mode::kRecord) {
    return std::vector<double>(xs.size(), 0.0);  // placeholders: the recording pass is thrown away
  }
  cache.misses += cache.recorded.size();
  cache.EvaluateRecorded();
  std::vector<double> objectives;
  for (const pagmo::vector_double& x : xs) objectives.push_back(cache.known.at(x));
  return objectives;
}

}  // namespace orcs::identify

PAGMO_S11N_PROBLEM_IMPLEMENT(orcs::identify::BatchProblem)
