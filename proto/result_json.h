// A result as one JSON object: the line format of results.jsonl (docs/batch.md) and of `orcs-sim --scenario`.
// Numbers are printed so that they read back as the same double (nlohmann-json prints the shortest text that
// round-trips), so a results file holds the exact bits of every fitness and term.
#pragma once

#include <nlohmann/json.hpp>
#include <string_view>

#include "orcs/v1/result.pb.h"

namespace orcs::proto {

/// The status as written in results.jsonl: "ok", "invalid_input", "unstable_physics", "timeout", "worker_lost",
/// "internal_error", "crashed", "script_error", "script_limit", "plugin_missing"
/// ("internal_error" also for an unset status).
std::string_view StatusName(v1::Result::Status status);

/// The result as {"id", "status", "fitness", "terms", "sets", "worker", "attempts", "timings", "message"}:
/// "terms" holds each term's mean over the parameter sets; "sets" holds per set its index, fitness, status,
/// message (when not ok), "drawn" (path → value) and "terms" (name → value). Logs are not included.
nlohmann::ordered_json ResultToJson(const v1::Result& result);

/// A results.jsonl line read back (a resumed batch's earlier results, `orcs-batch compare`): id, status, fitness,
/// message, engine, worker, attempts, timings and every set with its drawn values and terms — everything
/// ResultToJson writes but the mean terms, which follow from the sets. Throws std::invalid_argument naming the
/// field ("sets[2].fitness: ...") when the line is not such an object.
v1::Result ResultFromJson(const nlohmann::json& line);

}  // namespace orcs::proto
