#include "clients/evolve/evolution.h"

#include <algorithm>
#include <boost/archive/codecvt_null.hpp>
#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/math/special_functions/nonfinite_num_facets.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/de.hpp>
#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/algorithms/sga.hpp>
#include <pagmo/algorithms/xnes.hpp>
#include <sstream>

#include "base/demand.h"
#include "model/core/error.h"
#include "model/core/random_stream.h"

namespace orcs::evolve {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// pagmo seeds are 32 bits; the settings' seed is folded into them.
unsigned PagmoSeed(std::uint64_t seed) { return static_cast<unsigned>(seed ^ (seed >> 32)); }

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

pagmo::algorithm MakeAlgorithm(const EvolutionSettings& settings) {
  const unsigned seed = PagmoSeed(settings.seed);
  switch (settings.algorithm) {
    case Algorithm::kCmaes:
      // ftol = xtol = 0: pagmo's CMA-ES tests them *before* evaluating a generation and returns without evaluating
      // anything when the last population's objectives lie within ftol (or its step within xtol). A generation whose
      // jobs all failed (all kFailedObjective) or a fitness plateau would stall the run: every later generation
      // empty. The run does the generations it was asked for.
      return pagmo::algorithm{pagmo::cmaes(1, -1, -1, -1, -1, settings.sigma, 0.0, 0.0, true, true, seed)};
    case Algorithm::kXnes:
      return pagmo::algorithm{pagmo::xnes(1, -1, -1, -1, settings.sigma, 1e-6, 1e-6, true, true, seed)};
    case Algorithm::kSga:
      return pagmo::algorithm{pagmo::sga(1, .90, 1., .02, 1., 2u, "exponential", "polynomial", "tournament", seed)};
    case Algorithm::kDe:
      return pagmo::algorithm{pagmo::de(1, .8, .9, 2u, 1e-6, 1e-6, seed)};
    case Algorithm::kPsoGen:
      return pagmo::algorithm{pagmo::pso_gen(1, .7298, 2.05, 2.05, .5, 5u, 2u, 4u, true, seed)};
  }
  ORCS_UNREACHABLE("MakeAlgorithm: an algorithm the settings' parser lets through");
}

void CheckResumable(Algorithm algorithm, const std::string& source) {
  if (algorithm != Algorithm::kPsoGen) return;
  throw InputError(source +
                   ": a pso_gen run cannot be resumed: pagmo 2.18 does not save the particles' velocities, "
                   "so the continued search would differ from an uninterrupted run; start it afresh (or evolve with "
                   "cmaes, xnes, sga or de)");
}

Evolution::Evolution(EvolutionSettings settings, GenomeEvaluator evaluate)
    : settings_(std::move(settings)),
      evaluate_(std::move(evaluate)),
      cache_(std::make_shared<GenerationCache>()),
      algorithm_(MakeAlgorithm(settings_)),
      population_(pagmo::problem{BatchProblem{settings_.bounds.size(), cache_}}, 0u, PagmoSeed(settings_.seed)) {
  cache_->evaluate = [this](const std::vector<pagmo::vector_double>& xs) { return EvaluateBatch(xs); };
}

std::vector<double> Evolution::GenomeOf(const pagmo::vector_double& x) const {
  std::vector<double> genome(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const GeneBounds& b = settings_.bounds[i];
    genome[i] = std::clamp(b.low + x[i] * (b.high - b.low), b.low, b.high);
  }
  return genome;
}

pagmo::vector_double Evolution::DecisionVectorOf(const std::vector<double>& genome) const {
  pagmo::vector_double x(genome.size());
  for (std::size_t i = 0; i < genome.size(); ++i) {
    const GeneBounds& b = settings_.bounds[i];
    x[i] = std::clamp((genome[i] - b.low) / (b.high - b.low), 0.0, 1.0);
  }
  return x;
}

// The evaluator's answers as objectives; every ok answer competes for champion, in batch order (ties: first).
std::vector<double> Evolution::EvaluateBatch(const std::vector<pagmo::vector_double>& xs) {
  std::vector<std::vector<double>> genomes;
  for (const pagmo::vector_double& x : xs) genomes.push_back(GenomeOf(x));
  const std::uint64_t seed = GenerationSeed(settings_, evaluating_);
  const std::vector<Evaluation> evaluations = evaluate_(genomes, seed);
  ORCS_DEMAND_MSG(evaluations.size() == genomes.size(), "GenomeEvaluator: one evaluation per genome");
  std::vector<double> objectives;
  for (std::size_t i = 0; i < evaluations.size(); ++i) {
    const Evaluation& e = evaluations[i];
    current_.push_back(e);
    objectives.push_back(e.ok ? -e.fitness : kFailedObjective);
    if (e.ok && (champion_.genome.empty() || e.fitness > champion_.fitness)) {
      champion_ = {genomes[i], e.fitness, static_cast<int>(history_.size()), seed};
    }
  }
  return objectives;
}

void Evolution::Initialise() {
  const auto started = std::chrono::steady_clock::now();
  const std::size_t genes = settings_.bounds.size();
  std::vector<pagmo::vector_double> xs;
  if (!settings_.start.empty()) xs.push_back(DecisionVectorOf(settings_.start));
  for (std::size_t i = xs.size(); i < static_cast<std::size_t>(settings_.population); ++i) {
    RandomStream stream(settings_.seed, "evolve-initial-population", i);
    pagmo::vector_double x(genes);
    for (double& gene : x) gene = stream.Uniform();
    xs.push_back(std::move(x));
  }
  cache_->recorded = xs;
  evaluating_ = 0;
  cache_->EvaluateRecorded();
  for (const pagmo::vector_double& x : xs) population_.push_back(x, {cache_->known.at(x)});
  CloseGeneration(0, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

void Evolution::Step() {
  const auto started = std::chrono::steady_clock::now();
  cache_->known.clear();  // a generation evaluates what it asks for: a resumed run repeats the same jobs
  evaluating_ = generation() + 1;
  cache_->mode = GenerationCache::Mode::kRecord;
  pagmo::algorithm rehearsal = algorithm_;  // same random state: asks for what the real pass will
  rehearsal.evolve(population_);
  cache_->mode = GenerationCache::Mode::kLookup;
  cache_->EvaluateRecorded();
  population_ = algorithm_.evolve(population_);
  CloseGeneration(generation() + 1, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

void Evolution::CloseGeneration(int generation, double seconds) {
  GenerationRecord record;
  record.generation = generation;
  record.evaluations = current_.size();
  std::vector<double> ok;
  for (const Evaluation& e : current_) {
    if (e.ok) ok.push_back(e.fitness);
  }
  record.failed = current_.size() - ok.size();
  record.best = ok.empty() ? kNaN : *std::max_element(ok.begin(), ok.end());
  record.worst = ok.empty() ? kNaN : *std::min_element(ok.begin(), ok.end());
  record.mean = ok.empty() ? kNaN : std::accumulate(ok.begin(), ok.end(), 0.0) / static_cast<double>(ok.size());
  record.median = ok.empty() ? kNaN : Median(ok);
  record.best_so_far = champion_.genome.empty() ? kNaN : champion_.fitness;
  record.seconds = seconds;
  history_.push_back(record);
  current_.clear();
}

namespace {

// The locale a pagmo state is written and read in. Boost's text archives write NaN and ±inf but cannot read them
// back ("input stream error"); pagmo's state holds them (a NaN or infinite fitness, and pagmo 2.18's CMA-ES saves a
// vector it never initialises), so the archive streams use Boost.Math's facets that read what they wrote.
std::locale ArchiveLocale() {
  const std::locale plain(std::locale::classic(), new boost::archive::codecvt_null<char>);
  const std::locale with_put(plain, new boost::math::nonfinite_num_put<char>);
  return std::locale(with_put, new boost::math::nonfinite_num_get<char>);
}

}  // namespace

std::string Evolution::SaveState() const {
  std::ostringstream text;
  text.imbue(ArchiveLocale());
  {
    boost::archive::text_oarchive archive(text, boost::archive::no_codecvt);
    archive << algorithm_ << population_;
  }
  return text.str();
}

void Evolution::Restore(const std::string& state, std::vector<GenerationRecord> history, Champion champion,
                        const std::string& source) {
  CheckResumable(settings_.algorithm, source);
  try {
    std::istringstream text(state);
    text.imbue(ArchiveLocale());
    boost::archive::text_iarchive archive(text, boost::archive::no_codecvt);
    archive >> algorithm_ >> population_;
  } catch (const std::exception& error) {
    throw InputError(source + ": field 'pagmo_state' does not read back (" + error.what() + ")");
  }
  BatchProblem* problem = population_.get_problem().extract<BatchProblem>();
  if (problem == nullptr || population_.get_problem().get_nx() != settings_.bounds.size()) {
    throw InputError(source + ": field 'pagmo_state' holds another problem than this scenario's genome");
  }
  problem->Attach(cache_);
  history_ = std::move(history);
  champion_ = std::move(champion);
}

}  // namespace orcs::evolve
