#include "worker/job/job_translation.h"

#include <sys/resource.h>

#include <chrono>
#include <new>
#include <string>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text.h"
#include "model/scene/scenario.h"

namespace orcs::worker {
namespace {

v1::Result::Status StatusOf(evaluation::EvaluationStatus status) {
  switch (status) {
    case evaluation::EvaluationStatus::kOk: return v1::Result::OK;
    case evaluation::EvaluationStatus::kInvalidInput: return v1::Result::INVALID_INPUT;
    case evaluation::EvaluationStatus::kUnstablePhysics: return v1::Result::UNSTABLE_PHYSICS;
    case evaluation::EvaluationStatus::kTimeout: return v1::Result::TIMEOUT;
    case evaluation::EvaluationStatus::kInternalError: return v1::Result::INTERNAL_ERROR;
    case evaluation::EvaluationStatus::kScriptError: return v1::Result::SCRIPT_ERROR;
    case evaluation::EvaluationStatus::kScriptLimit: return v1::Result::SCRIPT_LIMIT;
    case evaluation::EvaluationStatus::kPluginMissing: return v1::Result::PLUGIN_MISSING;
  }
  return v1::Result::INTERNAL_ERROR;
}

// Why a job ran out of memory: the process's address-space limit when it has one (a sandbox's), else the machine's.
std::string OutOfMemoryMessage() {
  rlimit memory = {};
  if (::getrlimit(RLIMIT_AS, &memory) == 0 && memory.rlim_cur != RLIM_INFINITY) {
    return "out of memory: the simulation process may use at most " + std::to_string(memory.rlim_cur >> 20) +
           " MiB (orcs-worker --memory-limit); log fewer values, record less or raise the limit";
  }
  return "out of memory: an allocation failed (std::bad_alloc)";
}

}  // namespace

evaluation::EvaluationRequest RequestOf(const v1::Job& job, bool inject_faults,
                                        const script::PluginRegistry* plugins) {
  const std::string source = "job " + job.job_id();
  evaluation::EvaluationRequest request;
  request.scenario = scene::ParseScenario(ParseJson(job.scenario_json(), source + " scenario"), source + " scenario");
  request.genome = job.genome_json().empty() ? nlohmann::json::array() : ParseJson(job.genome_json(), source + " genome");
  request.seed = job.seed();
  for (const v1::Override& override : job.overrides()) {
    request.overrides.push_back({override.path(), override.value(), source + " override", 0});
  }
  const double limit = job.time_limit_seconds();
  if (!(limit >= 0.0 && limit <= evaluation::kMaxJobTimeLimitSeconds)) {  // NaN fails both
    throw InputError(source, 0,
                     "field 'time_limit_seconds' expected seconds from 0 (none) to " +
                         text::FormatDouble(evaluation::kMaxJobTimeLimitSeconds) + ", found " + text::FormatDouble(limit));
  }
  request.time_limit_seconds = limit;
  request.inject_faults = inject_faults;
  if (job.record()) {
    const int sets = request.scenario.randomisation.sets;
    if (job.record_set() >= static_cast<std::uint32_t>(sets)) {
      throw InputError(source + " record_set", 0,
                       "expected a parameter set of the job, 0…" + std::to_string(sets - 1) + ", found " +
                           std::to_string(job.record_set()));
    }
    request.record_set = static_cast<int>(job.record_set());
  }
  request.program = "orcs-worker";
  request.plugins = plugins;
  return request;
}

v1::Result ToResult(const v1::Job& job, const evaluation::EvaluationOutcome& outcome) {
  v1::Result result;
  result.set_job_id(job.job_id());
  result.set_batch_id(job.batch_id());
  result.set_status(StatusOf(outcome.status));
  result.set_message(text::ValidUtf8(outcome.message));  // may quote input bytes; must parse at the broker
  result.set_fitness(outcome.fitness);
  double simulated = 0.0;
  for (const evaluation::SetOutcome& set : outcome.sets) {
    v1::Result::ParameterSetResult* out = result.add_parameter_sets();
    out->set_index(static_cast<std::uint32_t>(set.index));
    for (const auto& [path, value] : set.drawn) {
      v1::DrawnValue* drawn = out->add_drawn();
      drawn->set_path(path);
      drawn->set_value(value);
    }
    for (const auto& [name, value] : set.terms) {
      v1::Term* term = out->add_terms();
      term->set_name(name);
      term->set_value(value);
    }
    out->set_fitness(set.fitness);
    out->set_status(StatusOf(set.status));
    out->set_message(text::ValidUtf8(set.message));
    simulated += set.simulated_seconds;
    if (!set.recording.empty()) result.set_recording(set.recording);
    if (!set.log_csv.empty()) {
      v1::LogFile* log = result.add_logs();
      log->set_name("set-" + std::to_string(set.index) + ".csv");
      log->set_csv(set.log_csv);
    }
  }
  result.set_engine(outcome.engine);
  result.mutable_timings()->set_run_seconds(outcome.wall_seconds);
  result.mutable_timings()->set_simulated_seconds(simulated);
  result.set_attempts(job.attempt() + 1);
  return result;
}

v1::Result RunJob(const v1::Job& job, bool inject_faults, const script::PluginRegistry* plugins) {
  const auto start = std::chrono::steady_clock::now();
  try {
    return ToResult(job, evaluation::Evaluate(RequestOf(job, inject_faults, plugins)));
  } catch (const InputError& error) {
    evaluation::EvaluationOutcome outcome;
    outcome.status = evaluation::EvaluationStatus::kInvalidInput;
    outcome.message = error.what();
    outcome.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return ToResult(job, outcome);
  } catch (const std::bad_alloc&) {
    evaluation::EvaluationOutcome outcome;
    outcome.message = OutOfMemoryMessage();
    outcome.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    v1::Result result = ToResult(job, outcome);
    result.set_status(v1::Result::CRASHED);  // the process's trouble, as when it dies: not the job's input's
    return result;
  } catch (const std::exception& error) {
    evaluation::EvaluationOutcome outcome;
    outcome.status = evaluation::EvaluationStatus::kInternalError;
    outcome.message = error.what();
    return ToResult(job, outcome);
  }
}

}  // namespace orcs::worker
