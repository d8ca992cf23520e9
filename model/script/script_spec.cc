#include "model/script/script_spec.h"

#include <lua.hpp>

#include "model/core/error.h"

namespace orcs::script {
namespace {

ScriptLimits LimitsOf(const JsonNode& entry) {
  ScriptLimits limits;
  if (!entry.Has("limits")) return limits;
  const JsonNode node = entry.At("limits");
  node.ExpectOnly({"instructions", "memory_mib"});
  if (node.Has("instructions")) {
    const JsonNode instructions = node.At("instructions");
    const std::uint64_t count = instructions.Unsigned("a number of instructions");
    if (count < 1000 || count > static_cast<std::uint64_t>(kMaxScriptInstructions)) {
      instructions.Fail("a number of instructions from 1000 to " + std::to_string(kMaxScriptInstructions));
    }
    limits.instructions = static_cast<std::int64_t>(count);
  }
  if (node.Has("memory_mib")) {
    const JsonNode memory = node.At("memory_mib");
    const std::uint64_t mib = memory.Unsigned("MiB");
    if (mib < 1 || mib > (kMaxScriptMemoryBytes >> 20)) {
      memory.Fail("MiB from 1 to " + std::to_string(kMaxScriptMemoryBytes >> 20));
    }
    limits.memory_bytes = static_cast<std::size_t>(mib) << 20;
  }
  return limits;
}

}  // namespace

ScriptSpec ParseScriptSpec(const JsonNode& entry) {
  ScriptSpec spec;
  const JsonNode script = entry.At("script");
  if (!script.value().is_object()) {
    script.Fail("an inlined script {\"file\", \"text\"} (resolve the scenario first) or {\"text\": \"...\"}");
  }
  script.ExpectOnly({"file", "text"});
  spec.text = script.At("text").String("the script's Lua source");
  spec.name = script.StringOr("file", entry.path() + ".script", "a file name");
  if (entry.Has("params")) {
    const JsonNode params = entry.At("params");
    if (!params.value().is_object()) params.Fail("an object of the script's parameters");
    spec.params = params.value();
  }
  spec.limits = LimitsOf(entry);
  ScriptSandbox::CheckSyntax(spec.name, spec.text);
  return spec;
}

namespace {

// Pushes `value` (see SetGlobal). Inside a protected call only: a refused allocation raises.
void PushJson(lua_State* state, const nlohmann::json& value) {
  luaL_checkstack(state, 4, "params");
  switch (value.type()) {
    case nlohmann::json::value_t::object:
      lua_createtable(state, 0, static_cast<int>(value.size()));
      for (auto it = value.begin(); it != value.end(); ++it) {
        PushJson(state, it.value());
        lua_setfield(state, -2, it.key().c_str());
      }
      return;
    case nlohmann::json::value_t::array:
      lua_createtable(state, static_cast<int>(value.size()), 0);
      for (std::size_t i = 0; i < value.size(); ++i) {
        PushJson(state, value[i]);
        lua_rawseti(state, -2, static_cast<lua_Integer>(i + 1));
      }
      return;
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: lua_pushinteger(state, value.get<lua_Integer>()); return;
    case nlohmann::json::value_t::number_float: lua_pushnumber(state, value.get<double>()); return;
    case nlohmann::json::value_t::string: lua_pushlstring(state, value.get_ref<const std::string&>().data(), value.get_ref<const std::string&>().size()); return;
    case nlohmann::json::value_t::boolean: lua_pushboolean(state, value.get<bool>()); return;
    default: lua_pushnil(state); return;
  }
}

// lua_pcall's trampoline: upvalue-free, the value and the name as light userdata.
int SetGlobalProtected(lua_State* state) {
  const auto* value = static_cast<const nlohmann::json*>(lua_touserdata(state, 1));
  const auto* name = static_cast<const char*>(lua_touserdata(state, 2));
  PushJson(state, *value);
  lua_setglobal(state, name);
  return 0;
}

}  // namespace

void SetGlobal(ScriptSandbox& sandbox, const char* name, const nlohmann::json& value) {
  lua_State* state = sandbox.state();
  lua_pushcfunction(state, SetGlobalProtected);
  lua_pushlightuserdata(state, const_cast<nlohmann::json*>(&value));
  lua_pushlightuserdata(state, const_cast<char*>(name));
  sandbox.CallStack(2, 0, name);
}

}  // namespace orcs::script
