#include "worker/sim/scenario_run.h"

#include <iostream>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text_file.h"
#include "model/evaluation/recorder.h"
#include "net/cli_style.h"
#include "model/evaluation/evaluation.h"
#include "worker/job/job_translation.h"
#include "proto/result_json.h"

namespace orcs::sim {
namespace {

nlohmann::json GenomeOf(const SimOptions& options, const scene::Scenario& scenario) {
  if (options.genome.starts_with("@")) {
    const std::string path = options.genome.substr(1);
    return ParseJson(ReadTextFile(path), path);
  }
  if (!options.genome.empty()) return ParseJson(options.genome, "--genome");
  return scenario.genome.is_null() ? nlohmann::json::array() : scenario.genome;
}

}  // namespace

int RunScenario(const SimOptions& options) {
  evaluation::EvaluationRequest request;
  nlohmann::json resolved = scene::ResolveScenarioFile(options.scenario);
  if (!options.engine.empty()) scene::SetScenarioEngine(resolved, options.engine);
  request.scenario = scene::ParseScenario(resolved, options.scenario);
  request.genome = GenomeOf(options, request.scenario);
  request.seed = options.seed;
  request.program = "orcs-sim";
  if (!options.record.empty()) request.record_set = options.record_set;
  const evaluation::EvaluationOutcome outcome = evaluation::Evaluate(request);
  if (outcome.status == evaluation::EvaluationStatus::kInvalidInput) throw InputError(outcome.message);
  if (!options.record.empty()) {
    if (options.record_set >= static_cast<int>(outcome.sets.size())) {
      throw InputError("--record-set", 0, "the scenario has parameter sets 0…" +
                                              std::to_string(outcome.sets.size() - 1) + ", found " +
                                              std::to_string(options.record_set));
    }
    evaluation::WriteRecording(options.record, outcome.sets[options.record_set].recording);
  }
  v1::Job job;
  job.set_job_id("orcs-sim");
  job.set_seed(options.seed);
  v1::Result result = worker::ToResult(job, outcome);
  result.set_worker_id("orcs-sim");
  nlohmann::ordered_json line = proto::ResultToJson(result);
  line["seed"] = options.seed;
  std::cout << line.dump() << std::endl;
  return outcome.status == evaluation::EvaluationStatus::kOk ? cli::kExitOk : cli::kExitRunFailed;
}

}  // namespace orcs::sim
