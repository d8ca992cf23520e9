// A script as a scenario names it (docs/extending.md): the fitness term {"type": "script", "script": "x.lua", ...}
// or the controller {"type": "script", "script": "x.lua", "genome_length": N, ...}. A scenario file gives the script
// as a file name; ResolveScenarioFile inlines it as {"file": "x.lua", "text": "..."}, so that the script travels
// inside the job and reaches every worker.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "model/core/json_node.h"
#include "model/script/script_sandbox.h"

namespace orcs::script {

struct ScriptSpec {
  std::string name;                        ///< the script's file name, for messages ("head_level.lua")
  std::string text;                        ///< its Lua source
  nlohmann::json params = nlohmann::json::object();  ///< "params": the script's global `params`, as Lua values
  ScriptLimits limits;                     ///< "limits": {"instructions": N, "memory_mib": M}
};

/// The script of `entry` (a fitness term or a controller section): its "script" ({"file", "text"} resolved, or
/// {"text"} inline), "params" (an object) and "limits". Throws InputError naming the field; compiles the script and
/// throws InputError "script name:line: message" for a syntax error — before any simulation.
ScriptSpec ParseScriptSpec(const JsonNode& entry);

/// Sets the script's global `name` to `value` as the Lua value it reads as: objects and arrays as tables (arrays from
/// index 1), numbers, strings, booleans; null as nil. Throws ScriptFailure when the memory cap cannot hold it.
void SetGlobal(ScriptSandbox& sandbox, const char* name, const nlohmann::json& value);

}  // namespace orcs::script
