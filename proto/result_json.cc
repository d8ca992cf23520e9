#include "proto/result_json.h"

#include <map>
#include <string>
#include <vector>

namespace orcs::proto {
namespace {

using Json = nlohmann::ordered_json;

Json SetToJson(const v1::Result::ParameterSetResult& set) {
  Json out;
  out["index"] = set.index();
  out["fitness"] = set.fitness();
  out["status"] = StatusName(set.status());
  if (!set.message().empty()) out["message"] = set.message();
  Json drawn = Json::object();
  for (const v1::DrawnValue& value : set.drawn()) drawn[value.path()] = value.value();
  out["drawn"] = std::move(drawn);
  Json terms = Json::object();
  for (const v1::Term& term : set.terms()) terms[term.name()] = term.value();
  out["terms"] = std::move(terms);
  return out;
}

// Each term's mean over the sets that report it, in the order the terms first appear.
Json MeanTerms(const v1::Result& result) {
  std::vector<std::string> order;
  std::map<std::string, std::pair<double, int>> sums;
  for (const v1::Result::ParameterSetResult& set : result.parameter_sets()) {
    for (const v1::Term& term : set.terms()) {
      auto [it, inserted] = sums.try_emplace(term.name(), 0.0, 0);
      if (inserted) order.push_back(term.name());
      it->second.first += term.value();
      ++it->second.second;
    }
  }
  Json terms = Json::object();
  for (const std::string& name : order) terms[name] = sums[name].first / sums[name].second;
  return terms;
}

}  // namespace

std::string_view StatusName(v1::Result::Status status) {
  switch (status) {
    case v1::Result::OK: return "ok";
    case v1::Result::INVALID_INPUT: return "invalid_input";
    case v1::Result::UNSTABLE_PHYSICS: return "unstable_physics";
    case v1::Result::TIMEOUT: return "timeout";
    case v1::Result::WORKER_LOST: return "worker_lost";
    case v1::Result::CRASHED: return "crashed";
    default: return "internal_error";
  }
}

Json ResultToJson(const v1::Result& result) {
  Json out;
  out["id"] = result.job_id();
  out["status"] = StatusName(result.status());
  if (result.status() == v1::Result::OK) {
    out["fitness"] = result.fitness();
  } else {
    out["fitness"] = nullptr;  // no valid fitness: null, so that no reader mistakes a 0 for one
  }
  out["terms"] = MeanTerms(result);
  Json sets = Json::array();
  for (const v1::Result::ParameterSetResult& set : result.parameter_sets()) sets.push_back(SetToJson(set));
  out["sets"] = std::move(sets);
  if (!result.engine().empty()) out["engine"] = result.engine();
  out["worker"] = result.worker_id();
  out["attempts"] = result.attempts();
  out["timings"] = {{"queued_seconds", result.timings().queued_seconds()},
                    {"run_seconds", result.timings().run_seconds()},
                    {"simulated_seconds", result.timings().simulated_seconds()}};
  out["message"] = result.message();
  return out;
}

}  // namespace orcs::proto
