// The one pagmo2 problem of orcs: decision vectors in the unit box, one objective to minimise, every value from a
// batch of jobs run through the broker. orcs-batch evolve (clients/evolve/evolution.h) minimises −fitness of
// genomes; the gap workflow's fits (model/identify/model_fit.cc) minimise the replays' squared error, calling batch_fitness through pagmo's member_bfe,
// so that each generation is one batch in lookup mode.
//
// pagmo 2.18's CMA-ES, xNES, SGA and DE ask for fitness values one at a time, but within a generation what they
// ask for does not depend on the answers: they sample the whole generation, then evaluate it. So each generation
// runs twice (Evolution::Step): a *recording* pass on copies of the algorithm and population collects the decision
// vectors the generation will need (answering with placeholders), those are evaluated as one batch, and the real
// pass finds every answer in the cache. The copies carry the same random state, so the real pass asks for exactly
// the recorded vectors, and the search is bit for bit the one pagmo would run with direct evaluations. A vector
// that was not recorded (an algorithm that does look at answers mid-generation) is evaluated on its own: slower,
// never wrong; GenerationCache::misses counts them.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <pagmo/problem.hpp>
#include <pagmo/s11n.hpp>
#include <pagmo/types.hpp>
#include <string>
#include <utility>
#include <vector>

namespace orcs::identify {

/// Shared by every copy pagmo makes of a BatchProblem.
struct GenerationCache {
  enum class Mode {
    kRecord,  ///< remember what is asked for, answer with placeholders
    kLookup,  ///< answer from `known`, evaluating what is missing
  };
  /// Evaluates decision vectors as one batch; returns one objective (to minimise) per vector, in order.
  using Evaluator = std::function<std::vector<double>(const std::vector<pagmo::vector_double>&)>;

  Mode mode = Mode::kLookup;                     ///< current pass
  std::vector<pagmo::vector_double> recorded;    ///< asked for in record mode, in order, without repeats
  std::map<pagmo::vector_double, double> known;  ///< evaluated vectors → objective
  Evaluator evaluate;                            ///< the batch back end (the broker)
  std::size_t misses = 0;                        ///< lookups evaluated alone because they were not recorded

  /// Evaluates the recorded vectors as one batch, files them in `known` and clears `recorded`.
  void EvaluateRecorded();
};

class BatchProblem {
 public:
  BatchProblem() = default;  ///< for pagmo's serialisation; Attach() a cache before use
  BatchProblem(std::size_t dimension, std::shared_ptr<GenerationCache> cache);

  /// pagmo's interface: one objective, −fitness of the genome the unit-box vector `x` maps to.
  pagmo::vector_double fitness(const pagmo::vector_double& x) const;
  /// pagmo's batch interface (member_bfe): the concatenated vectors, evaluated as one batch.
  pagmo::vector_double batch_fitness(const pagmo::vector_double& xs) const;
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const;
  std::string get_name() const { return "orcs genome (unit box)"; }

  /// Connects a problem read back from a checkpoint to this run's cache.
  void Attach(std::shared_ptr<GenerationCache> cache) { cache_ = std::move(cache); }

  template <typename Archive>
  void serialize(Archive& archive, unsigned /*version*/) {
    archive& dimension_;  // the cache is this run's, re-attached after loading
  }

 private:
  std::vector<double> Answer(const std::vector<pagmo::vector_double>& xs) const;

  std::size_t dimension_ = 1;               ///< genes
  std::shared_ptr<GenerationCache> cache_;  ///< shared with Evolution
};

}  // namespace orcs::identify

// pagmo's PAGMO_S11N_PROBLEM_EXPORT_KEY, with the key the class had when it lived in clients/evolve: evolve's
// checkpoints store the key, and checkpoints written before the move must still load.
BOOST_CLASS_EXPORT_KEY2(pagmo::detail::prob_inner<orcs::identify::BatchProblem>, "udp orcs::evolve::BatchProblem")
BOOST_CLASS_TRACKING(pagmo::detail::prob_inner<orcs::identify::BatchProblem>, boost::serialization::track_never)
