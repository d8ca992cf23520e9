#include "proto/result_json.h"

#include <map>
#include <stdexcept>
#include <type_traits>
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

v1::Result::Status StatusFromName(const std::string& name, const std::string& field) {
  for (v1::Result::Status status : {v1::Result::OK, v1::Result::INVALID_INPUT, v1::Result::UNSTABLE_PHYSICS,
                                    v1::Result::TIMEOUT, v1::Result::WORKER_LOST, v1::Result::CRASHED,
                                    v1::Result::INTERNAL_ERROR, v1::Result::SCRIPT_ERROR, v1::Result::SCRIPT_LIMIT,
                                    v1::Result::PLUGIN_MISSING}) {
    if (StatusName(status) == name) return status;
  }
  throw std::invalid_argument(field + ": unknown status '" + name + "'");
}

// `object[key]` as T, or `fallback` when absent; a wrong type names `where`.
template <typename T>
T Field(const nlohmann::json& object, const char* key, const std::string& where, T fallback = T{}) {
  const auto found = object.find(key);
  if (found == object.end() || found->is_null()) return fallback;
  try {
    return found->get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(where + key + ": expected " + (std::is_arithmetic_v<T> ? "a number" : "text") +
                                ", found " + found->dump().substr(0, 40));
  }
}

// The name → number pairs of `object[key]` (drawn values, terms), in the file's order.
template <typename Add>
void ReadPairs(const nlohmann::json& object, const char* key, const std::string& where, Add add) {
  const auto found = object.find(key);
  if (found == object.end()) return;
  if (!found->is_object()) throw std::invalid_argument(where + key + ": expected an object");
  for (auto it = found->begin(); it != found->end(); ++it) {
    if (!it->is_number()) throw std::invalid_argument(where + key + "." + it.key() + ": expected a number");
    add(it.key(), it->get<double>());
  }
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
    case v1::Result::SCRIPT_ERROR: return "script_error";
    case v1::Result::SCRIPT_LIMIT: return "script_limit";
    case v1::Result::PLUGIN_MISSING: return "plugin_missing";
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

v1::Result ResultFromJson(const nlohmann::json& line) {
  if (!line.is_object()) throw std::invalid_argument("expected a JSON object");
  v1::Result result;
  result.set_protocol_version(1);
  result.set_job_id(Field<std::string>(line, "id", ""));
  if (result.job_id().empty()) throw std::invalid_argument("id: missing or empty");
  result.set_status(StatusFromName(Field<std::string>(line, "status", ""), "status"));
  result.set_fitness(Field<double>(line, "fitness", ""));
  result.set_message(Field<std::string>(line, "message", ""));
  result.set_engine(Field<std::string>(line, "engine", ""));
  result.set_worker_id(Field<std::string>(line, "worker", ""));
  result.set_attempts(Field<std::uint32_t>(line, "attempts", ""));
  if (const auto timings = line.find("timings"); timings != line.end() && timings->is_object()) {
    result.mutable_timings()->set_queued_seconds(Field<double>(*timings, "queued_seconds", "timings."));
    result.mutable_timings()->set_run_seconds(Field<double>(*timings, "run_seconds", "timings."));
    result.mutable_timings()->set_simulated_seconds(Field<double>(*timings, "simulated_seconds", "timings."));
  }
  const auto sets = line.find("sets");
  if (sets == line.end()) return result;
  if (!sets->is_array()) throw std::invalid_argument("sets: expected an array");
  for (std::size_t i = 0; i < sets->size(); ++i) {
    const nlohmann::json& set = (*sets)[i];
    const std::string where = "sets[" + std::to_string(i) + "].";
    if (!set.is_object()) throw std::invalid_argument(where.substr(0, where.size() - 1) + ": expected an object");
    v1::Result::ParameterSetResult& out = *result.add_parameter_sets();
    out.set_index(Field<std::uint32_t>(set, "index", where));
    out.set_fitness(Field<double>(set, "fitness", where));
    out.set_status(StatusFromName(Field<std::string>(set, "status", where, "ok"), where + "status"));
    out.set_message(Field<std::string>(set, "message", where));
    ReadPairs(set, "drawn", where, [&](const std::string& path, double value) {
      v1::DrawnValue& drawn = *out.add_drawn();
      drawn.set_path(path);
      drawn.set_value(value);
    });
    ReadPairs(set, "terms", where, [&](const std::string& name, double value) {
      v1::Term& term = *out.add_terms();
      term.set_name(name);
      term.set_value(value);
    });
  }
  return result;
}

}  // namespace orcs::proto
