#include "clients/gap/broker_replays.h"

#include <cmath>
#include <sstream>

#include "model/core/error.h"
#include "model/core/text.h"
#include "model/scene/scenario.h"

namespace orcs::gap {

using identify::Override;
using identify::ReplayOutcome;
using identify::ReplayRequest;
using identify::ReplayRun;

namespace {

// A replay that stopped at its bound simulated less than the run lasts (at least one step less).
bool StoppedEarly(const v1::Result& result, const ReplayRun& run) {
  constexpr double kClockSlack = 1e-6;  // s: far below a step, far above the rounding of summed steps
  return result.timings().simulated_seconds() < run.scenario["duration"].get<double>() - kClockSlack;
}

}  // namespace

std::vector<ReplayOutcome> BrokerReplays::Replay(const std::vector<ReplayRequest>& requests) {
  std::vector<v1::Job> jobs;
  for (const ReplayRequest& request : requests) {
    jobs.push_back(MakeReplayJob(request));
    jobs.back().set_record(request.record);
  }
  std::vector<v1::Result> results = jobs_.Run(std::move(jobs));
  std::vector<ReplayOutcome> outcomes(requests.size());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    v1::Result& result = results[i];
    ReplayOutcome& outcome = outcomes[i];
    outcome.ok = result.status() == v1::Result::OK;
    outcome.error = result.fitness();
    outcome.recording = std::move(*result.mutable_recording());
    outcome.stopped_early = outcome.ok && StoppedEarly(result, *requests[i].run);
    if (outcome.stopped_early) ++stopped_early_;
    if (outcome.ok && requests[i].log && result.logs_size() > 0) {
      outcome.columns = ParseLogColumns(result.logs(0).csv(), requests[i].run->name);
    }
  }
  return outcomes;
}

v1::Job MakeReplayJob(const ReplayRequest& request) {
  nlohmann::json scenario = request.run->scenario;
  if (request.log) {
    const std::string quantities = request.run->accelerometers.empty() ? "JointAngle|MotorTorque"
                                                                        : "JointAngle|MotorTorque|AccelAxis1|AccelAxis2";
    scenario["log"] = {"/Sim/" + scenario["agent"].get<std::string>() + "/.*/(" + quantities + ")"};
  }
  nlohmann::json& term = scenario["fitness"]["terms"][0];
  if (request.loss == identify::Loss::kAbsolute) term["norm"] = "mean_absolute";
  if (std::isfinite(request.stop_above)) term["stop_above"] = request.stop_above;
  v1::Job job;
  job.set_scenario_json(scenario.dump());
  job.set_genome_json("[]");
  job.set_seed(0);
  job.set_time_limit_seconds(scene::DefaultTimeLimitSeconds(scenario["duration"].get<double>()));
  for (const Override& entry : request.overrides) {
    v1::Override* override_value = job.add_overrides();
    override_value->set_path(entry.first);
    override_value->set_value(entry.second);
  }
  return job;
}

std::vector<std::pair<std::string, std::vector<double>>> ParseLogColumns(const std::string& csv,
                                                                         const std::string& source) {
  std::vector<std::pair<std::string, std::vector<double>>> columns;
  std::istringstream lines(csv);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("# columns: ", 0) == 0) {
      for (std::string_view name : text::Split(std::string_view(line).substr(11), ',')) {
        columns.emplace_back(std::string(text::Trim(name)), std::vector<double>{});
      }
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    if (columns.empty()) throw InputError(source + ": no '# columns:' line before the data");
    const std::vector<std::string_view> fields = text::Split(line, ',');
    for (std::size_t c = 0; c < columns.size() && c < fields.size(); ++c) {
      columns[c].second.push_back(text::ParseDouble(fields[c]).value_or(std::nan("")));
    }
  }
  if (columns.empty()) throw InputError(source + ": no '# columns:' line");
  return columns;
}

}  // namespace orcs::gap
