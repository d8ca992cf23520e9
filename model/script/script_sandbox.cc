#include "model/script/script_sandbox.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <lua.hpp>

#include "model/core/error.h"

namespace orcs::script {
namespace {

// The count hook fires every this many VM instructions: the budget is kept to within one slice, at no measurable
// cost per instruction.
constexpr int kHookInterval = 1000;
// A script's error message is cut to this many bytes, on one line: a huge message must not travel with the result.
constexpr std::size_t kMaxMessageBytes = 300;
// What every refused library function says after its name.
constexpr const char* kSandboxHint =
    "is not available in orcs scripts: they cannot open files, run processes, read clocks, load code or use the "
    "network (docs/extending.md, \"The sandbox\")";

// Copies at most kMaxMessageBytes of `text` into `out` (size kMaxMessageBytes + 4), newlines and tabs as spaces,
// "..." where it was cut.
void OneLine(const char* text, std::size_t length, char* out) {
  const std::size_t kept = std::min(length, kMaxMessageBytes);
  for (std::size_t i = 0; i < kept; ++i) out[i] = (text[i] == '\n' || text[i] == '\r' || text[i] == '\t') ? ' ' : text[i];
  std::size_t end = kept;
  if (kept < length) {
    std::memcpy(out + end, "...", 3);
    end += 3;
  }
  out[end] = '\0';
}

// A library function the sandbox refuses, by name (its upvalue): raises "<name> is not available ...".
int Refused(lua_State* state) {
  return luaL_error(state, "%s %s", lua_tostring(state, lua_upvalueindex(1)), kSandboxHint);
}

void SetRefused(lua_State* state, int table, const char* key, const char* shown) {
  lua_pushstring(state, shown);
  lua_pushcclosure(state, Refused, 1);
  lua_setfield(state, table, key);
}

// __index of a refused library table (os, io, debug, package): every member is refused by its full name.
int RefusedMember(lua_State* state) {
  const char* library = lua_tostring(state, lua_upvalueindex(1));
  const char* member = lua_type(state, 2) == LUA_TSTRING ? lua_tostring(state, 2) : "?";
  return luaL_error(state, "%s.%s %s", library, member, kSandboxHint);
}

void SetRefusedLibrary(lua_State* state, const char* library) {
  lua_newtable(state);                 // the stand-in
  lua_newtable(state);                 // its metatable
  lua_pushstring(state, library);
  lua_pushcclosure(state, RefusedMember, 1);
  lua_setfield(state, -2, "__index");
  lua_setmetatable(state, -2);
  lua_setglobal(state, library);
}

// tostring without addresses: a table, function or userdata without __tostring or __name shows its type only,
// so that no text a script makes differs between runs.
void PushPlainString(lua_State* state, int index) {
  const int type = lua_type(state, index);
  const bool addressed = type == LUA_TTABLE || type == LUA_TFUNCTION || type == LUA_TUSERDATA ||
                         type == LUA_TTHREAD || type == LUA_TLIGHTUSERDATA;
  if (addressed && luaL_getmetafield(state, index, "__tostring") == LUA_TNIL &&
      luaL_getmetafield(state, index, "__name") == LUA_TNIL) {
    lua_pushstring(state, lua_typename(state, type));
    return;
  }
  if (addressed) lua_pop(state, 1);  // the metafield found
  luaL_tolstring(state, index, nullptr);
}

int PlainToString(lua_State* state) {
  luaL_checkany(state, 1);
  PushPlainString(state, 1);
  return 1;
}

// string.format without "%p" (an address), and with tables and functions shown as by PlainToString.
int PlainFormat(lua_State* state) {
  std::size_t length = 0;
  const char* format = luaL_checklstring(state, 1, &length);
  for (std::size_t i = 0; i + 1 < length; ++i) {
    if (format[i] != '%') continue;
    std::size_t j = i + 1;
    if (format[j] == '%') {
      i = j;
      continue;
    }
    while (j < length && std::strchr("-+ #0123456789.", format[j]) != nullptr) ++j;
    if (j < length && format[j] == 'p') return luaL_error(state, "string.format: %%p (an address) %s", kSandboxHint);
    i = j;
  }
  const int top = lua_gettop(state);
  for (int k = 2; k <= top; ++k) {
    const int type = lua_type(state, k);
    if (type == LUA_TTABLE || type == LUA_TFUNCTION || type == LUA_TUSERDATA || type == LUA_TTHREAD ||
        type == LUA_TLIGHTUSERDATA) {
      PushPlainString(state, k);
      lua_replace(state, k);
    }
  }
  lua_getfield(state, lua_upvalueindex(1), "format");  // the original string.format
  lua_insert(state, 1);
  lua_call(state, top, 1);
  return 1;
}

// string.rep that returns at once when the result is empty: the library's own loops n times even then, an
// unbounded loop inside one instruction the budget cannot see.
int BoundedRep(lua_State* state) {
  std::size_t length = 0, separator = 0;
  luaL_checklstring(state, 1, &length);
  const lua_Integer count = luaL_checkinteger(state, 2);
  luaL_optlstring(state, 3, "", &separator);
  if (count <= 0 || length + separator == 0) {
    lua_pushliteral(state, "");
    return 1;
  }
  lua_getfield(state, lua_upvalueindex(1), "rep");
  lua_insert(state, 1);
  lua_call(state, lua_gettop(state) - 1, 1);
  return 1;
}

// math.random with Lua's own signature — random(), random(m), random(m, n) — drawing from the sandbox's stream.
int StreamRandom(lua_State* state) {
  RandomStream& random = ScriptSandbox::Of(state).random();
  const int arguments = lua_gettop(state);
  if (arguments == 0) {
    lua_pushnumber(state, random.Uniform());
    return 1;
  }
  lua_Integer low = 1, high = 0;
  if (arguments == 1) {
    high = luaL_checkinteger(state, 1);
  } else if (arguments == 2) {
    low = luaL_checkinteger(state, 1);
    high = luaL_checkinteger(state, 2);
  } else {
    return luaL_error(state, "math.random: wrong number of arguments (0, 1 or 2)");
  }
  luaL_argcheck(state, low <= high, arguments, "interval is empty");
  const auto span = static_cast<std::uint64_t>(high) - static_cast<std::uint64_t>(low);
  const std::uint64_t offset = span == UINT64_MAX ? random.NextU64() : random.UniformInt(span + 1);
  lua_pushinteger(state, static_cast<lua_Integer>(static_cast<std::uint64_t>(low) + offset));
  return 1;
}

// One key of a table, for pairs' fixed order: numbers ascending, then strings in byte order, then false, true.
struct OrderedKey {
  int rank;            // 0 number, 1 string, 2 boolean
  double number;       // rank 0 (integers as doubles; ties broken by `integer`)
  lua_Integer integer;
  const char* text;    // rank 1 (held by the table while the keys are sorted)
  std::size_t length;
  int slot;            // where the key itself waits in the scratch table
};

bool KeyBefore(const OrderedKey& a, const OrderedKey& b) {
  if (a.rank != b.rank) return a.rank < b.rank;
  if (a.rank == 0) return a.number != b.number ? a.number < b.number : a.integer < b.integer;
  if (a.rank == 1) {
    const int order = std::memcmp(a.text, b.text, std::min(a.length, b.length));
    return order != 0 ? order < 0 : a.length < b.length;
  }
  return a.integer < b.integer;
}

// The iterator pairs returns: upvalue 1 the table, 2 the keys in order, 3 the next position.
int OrderedNext(lua_State* state) {
  const lua_Integer position = lua_tointeger(state, lua_upvalueindex(3));
  if (lua_rawgeti(state, lua_upvalueindex(2), position) == LUA_TNIL) return 1;
  lua_pushinteger(state, position + 1);
  lua_replace(state, lua_upvalueindex(3));
  lua_pushvalue(state, -1);
  lua_gettable(state, lua_upvalueindex(1));
  return 2;
}

// pairs(t) in a fixed order (the keys sorted as KeyBefore says; a key of another type is an error), so that a sum
// over a table's members is the same bits on every run: Lua's own order follows a per-process string hash seed.
// A __pairs metamethod is honoured.
int OrderedPairs(lua_State* state) {
  luaL_checkany(state, 1);
  if (luaL_getmetafield(state, 1, "__pairs") != LUA_TNIL) {
    lua_pushvalue(state, 1);
    lua_call(state, 1, 3);
    return 3;
  }
  luaL_checktype(state, 1, LUA_TTABLE);
  lua_settop(state, 1);
  lua_newtable(state);  // 2: the keys as found
  int count = 0;
  lua_pushnil(state);
  while (lua_next(state, 1) != 0) {
    lua_pop(state, 1);
    const int type = lua_type(state, -1);
    if (type != LUA_TNUMBER && type != LUA_TSTRING && type != LUA_TBOOLEAN) {
      return luaL_error(state, "pairs: a table with a %s key has no fixed order; use ipairs or string keys",
                        luaL_typename(state, -1));
    }
    lua_pushvalue(state, -1);
    lua_rawseti(state, 2, ++count);
  }
  // Scratch memory the Lua state owns (no C++ destructor to skip if an allocation below raises).
  auto* keys = static_cast<OrderedKey*>(lua_newuserdatauv(state, sizeof(OrderedKey) * (count + 1), 0));  // 3
  for (int k = 1; k <= count; ++k) {
    lua_rawgeti(state, 2, k);
    OrderedKey& key = keys[k - 1];
    key = {0, 0.0, 0, nullptr, 0, k};
    switch (lua_type(state, -1)) {
      case LUA_TNUMBER:
        key.number = lua_tonumber(state, -1);
        key.integer = lua_isinteger(state, -1) ? lua_tointeger(state, -1) : 0;
        break;
      case LUA_TSTRING: key.rank = 1; key.text = lua_tolstring(state, -1, &key.length); break;
      default: key.rank = 2; key.integer = lua_toboolean(state, -1); break;
    }
    lua_pop(state, 1);
  }
  std::sort(keys, keys + count, KeyBefore);
  lua_pushcfunction(state, OrderedNext);  // 4
  lua_pushvalue(state, 1);
  lua_createtable(state, count, 0);
  for (int k = 0; k < count; ++k) {
    lua_rawgeti(state, 2, keys[k].slot);
    lua_rawseti(state, -2, k + 1);
  }
  lua_pushinteger(state, 1);
  lua_pushcclosure(state, OrderedNext, 3);
  return 1;
}

// "64 MiB" for whole mebibytes, else "N bytes".
std::string Bytes(std::size_t bytes) {
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  return bytes % kMiB == 0 ? std::to_string(bytes / kMiB) + " MiB" : std::to_string(bytes) + " bytes";
}

// The line of the innermost Lua function running on `state`, 0 when none is.
int CurrentLine(lua_State* state) {
  lua_Debug frame;
  for (int level = 0; lua_getstack(state, level, &frame) != 0; ++level) {
    if (lua_getinfo(state, "l", &frame) != 0 && frame.currentline > 0) return frame.currentline;
  }
  return 0;
}

}  // namespace

ScriptSandbox& ScriptSandbox::Of(lua_State* state) {
  return **static_cast<ScriptSandbox**>(lua_getextraspace(state));
}

void* ScriptSandbox::Allocate(void* self, void* block, std::size_t old_size, std::size_t new_size) {
  auto& sandbox = *static_cast<ScriptSandbox*>(self);
  const std::size_t held = block == nullptr ? 0 : old_size;  // for a new block, old_size is its type
  if (new_size == 0) {
    std::free(block);
    sandbox.bytes_ -= held;
    return nullptr;
  }
  if (new_size > held && sandbox.bytes_ - held + new_size > sandbox.limits_.memory_bytes) {
    // Where the script was: the error Lua raises for a refused block carries no position.
    if (sandbox.state_ != nullptr) sandbox.memory_line_ = CurrentLine(sandbox.state_);
    return nullptr;
  }
  void* grown = std::realloc(block, new_size);
  if (grown != nullptr) sandbox.bytes_ = sandbox.bytes_ - held + new_size;
  return grown;
}

void ScriptSandbox::CountHook(lua_State* state, lua_Debug* where) {
  ScriptSandbox& sandbox = Of(state);
  sandbox.used_ += kHookInterval;
  if (sandbox.used_ <= sandbox.limits_.instructions && !sandbox.over_budget_) return;
  if (!sandbox.over_budget_) {
    sandbox.over_budget_ = true;
    sandbox.limit_line_ = lua_getinfo(state, "l", where) != 0 ? where->currentline : 0;
  }
  luaL_error(state, "instruction budget exceeded");  // raised again at every hook: no pcall can go on past it
}

// pcall and xpcall that let no limit be caught: after one, the error goes on up to orcs.
int ScriptSandbox::ProtectedCall(lua_State* state) {
  luaL_checkany(state, 1);
  lua_pushnil(state);  // the slot pcall's first result takes
  lua_insert(state, 1);
  return PcallResults(state, lua_pcall(state, lua_gettop(state) - 2, LUA_MULTRET, 0));
}

int ScriptSandbox::PcallResults(lua_State* state, int status) {
  ScriptSandbox& sandbox = Of(state);
  if (status == LUA_ERRMEM) sandbox.out_of_memory_ = true;
  if (status != LUA_OK && (sandbox.over_budget_ || sandbox.out_of_memory_)) return lua_error(state);
  lua_pushboolean(state, status == LUA_OK);
  lua_replace(state, 1);
  return lua_gettop(state);
}

int ScriptSandbox::ProtectedCallWithHandler(lua_State* state) {
  const int arguments = lua_gettop(state) - 2;
  luaL_checktype(state, 2, LUA_TFUNCTION);
  luaL_checkany(state, 1);
  lua_pushvalue(state, 1);  // [f, handler, args..., f]
  lua_pushvalue(state, 2);  // [..., f, handler]
  lua_replace(state, 1);    // [handler, handler, args..., f]
  lua_replace(state, 2);    // [handler, f, args...]
  return PcallResults(state, lua_pcall(state, arguments, LUA_MULTRET, 1));
}

void ScriptSandbox::OpenLibraries() {
  lua_State* L = state_;
  struct Library {
    const char* name;
    lua_CFunction open;
  };
  for (const Library& library : {Library{LUA_GNAME, luaopen_base}, Library{LUA_TABLIBNAME, luaopen_table},
                                 Library{LUA_STRLIBNAME, luaopen_string}, Library{LUA_MATHLIBNAME, luaopen_math},
                                 Library{LUA_UTF8LIBNAME, luaopen_utf8}}) {
    luaL_requiref(L, library.name, library.open, 1);
    lua_pop(L, 1);
  }
  lua_pushglobaltable(L);
  const int globals = lua_gettop(L);
  for (const char* name : {"dofile", "loadfile", "load", "loadstring", "require", "collectgarbage", "next"}) {
    SetRefused(L, globals, name, name);
  }
  lua_pushcfunction(L, [](lua_State*) { return 0; });  // print goes nowhere: a job has no console
  lua_setfield(L, globals, "print");
  lua_pushcfunction(L, PlainToString);
  lua_setfield(L, globals, "tostring");
  lua_pushcfunction(L, OrderedPairs);
  lua_setfield(L, globals, "pairs");
  lua_pushcfunction(L, ProtectedCall);
  lua_setfield(L, globals, "pcall");
  lua_pushcfunction(L, ProtectedCallWithHandler);
  lua_setfield(L, globals, "xpcall");
  for (const char* library : {"os", "io", "debug", "package", "coroutine"}) SetRefusedLibrary(L, library);

  // string: no code (dump), no patterns (their backtracking can run for ever inside one instruction).
  lua_getglobal(L, LUA_STRLIBNAME);
  const int strings = lua_gettop(L);
  lua_newtable(L);  // the originals, for the wrappers
  lua_getfield(L, strings, "format");
  lua_setfield(L, -2, "format");
  lua_getfield(L, strings, "rep");
  lua_setfield(L, -2, "rep");
  const int originals = lua_gettop(L);
  lua_pushvalue(L, originals);
  lua_pushcclosure(L, PlainFormat, 1);
  lua_setfield(L, strings, "format");
  lua_pushvalue(L, originals);
  lua_pushcclosure(L, BoundedRep, 1);
  lua_setfield(L, strings, "rep");
  SetRefused(L, strings, "dump", "string.dump");
  for (const char* name : {"find", "match", "gmatch", "gsub", "pack", "packsize", "unpack"}) {
    lua_pushfstring(L, "string.%s", name);
    lua_pushcclosure(L, Refused, 1);
    lua_setfield(L, strings, name);
  }
  lua_settop(L, globals);

  // table.move loops over its whole range inside one instruction, even over nothing.
  lua_getglobal(L, LUA_TABLIBNAME);
  SetRefused(L, lua_gettop(L), "move", "table.move");
  lua_pop(L, 1);
  // math.random from orcs's seeded stream; no reseeding.
  lua_getglobal(L, LUA_MATHLIBNAME);
  lua_pushcfunction(L, StreamRandom);
  lua_setfield(L, -2, "random");
  SetRefused(L, lua_gettop(L), "randomseed", "math.randomseed");
  lua_settop(L, 0);
}

ScriptSandbox::ScriptSandbox(std::string name, const ScriptLimits& limits) : name_(std::move(name)), limits_(limits) {
  state_ = lua_newstate(Allocate, this);
  if (state_ == nullptr) throw ScriptFailure(ScriptFailure::Kind::kLimit, "script '" + name_ + "': no memory for its state");
  *static_cast<ScriptSandbox**>(lua_getextraspace(state_)) = this;
  OpenLibraries();
  lua_sethook(state_, CountHook, LUA_MASKCOUNT, kHookInterval);
}

ScriptSandbox::~ScriptSandbox() {
  if (state_ != nullptr) lua_close(state_);
}

void ScriptSandbox::CheckSyntax(const std::string& name, const std::string& text) {
  ScriptSandbox(name, ScriptLimits{}).Compile(text);
}

void ScriptSandbox::Run(const std::string& text) {
  Compile(text);
  CallStack(0, 0, "its top level");
}

void ScriptSandbox::Compile(const std::string& text) {
  if (!text.empty() && text[0] == LUA_SIGNATURE[0]) {
    throw InputError(name_, 0, "is a compiled Lua chunk; orcs runs scripts from their source text only");
  }
  const std::string chunk = "=" + name_;
  const int status = luaL_loadbufferx(state_, text.data(), text.size(), chunk.c_str(), "t");
  if (status != LUA_OK) {
    if (status == LUA_ERRMEM) throw FailureOf(status, "its compilation");
    char line[kMaxMessageBytes + 4];
    std::size_t length = 0;
    const char* message = lua_tolstring(state_, -1, &length);
    OneLine(message != nullptr ? message : "?", message != nullptr ? length : 1, line);
    lua_pop(state_, 1);
    // Lua says "name:12: message"; an InputError names the script as a source with a line already.
    throw InputError(std::string("script ") + line);
  }
}

int ScriptSandbox::FunctionRef(const char* function) const {
  const int type = lua_getglobal(state_, function);
  if (type == LUA_TNIL) {
    lua_pop(state_, 1);
    return LUA_NOREF;
  }
  if (type != LUA_TFUNCTION) {
    lua_pop(state_, 1);
    throw ScriptFailure(ScriptFailure::Kind::kError, "script '" + name_ + "': global '" + function +
                                                         "' expected a function, found a " + lua_typename(state_, type));
  }
  return luaL_ref(state_, LUA_REGISTRYINDEX);
}

void ScriptSandbox::Call(int ref, const char* function, int arguments, int results) {
  lua_rawgeti(state_, LUA_REGISTRYINDEX, ref);
  lua_insert(state_, -arguments - 1);
  CallStack(arguments, results, function);
}

void ScriptSandbox::CallStack(int arguments, int results, const char* what) {
  const int status = lua_pcall(state_, arguments, results, 0);
  if (status != LUA_OK) throw FailureOf(status, what);
}

void ScriptSandbox::StartSet(std::uint64_t seed) {
  used_ = 0;
  random_ = RandomStream(seed, "script " + name_);
}

ScriptFailure ScriptSandbox::FailureOf(int status, const char* function) {
  if (status == LUA_ERRMEM) out_of_memory_ = true;
  char line[kMaxMessageBytes + 4] = "(an error value that is not text)";
  if (lua_type(state_, -1) == LUA_TSTRING || lua_type(state_, -1) == LUA_TNUMBER) {
    std::size_t length = 0;
    const char* message = lua_tolstring(state_, -1, &length);
    OneLine(message, length, line);
  }
  lua_pop(state_, 1);
  const std::string where = "script '" + name_ + "'";
  if (over_budget_) {
    return {ScriptFailure::Kind::kLimit, where + " line " + std::to_string(limit_line_) + ": instruction budget of " +
                                             std::to_string(limits_.instructions) + " per parameter set exceeded in " +
                                             function + " (raise it with \"limits\": {\"instructions\": N} beside the script)"};
  }
  if (out_of_memory_) {
    return {ScriptFailure::Kind::kLimit, where + " line " + std::to_string(memory_line_) + ": memory cap of " +
                                             Bytes(limits_.memory_bytes) + " exceeded in " + function +
                                             " (raise it with \"limits\": {\"memory_mib\": N} beside the script)"};
  }
  // Lua's runtime errors begin "name:line:", which names the script and the line already.
  const std::string message = line;
  if (message.starts_with(name_ + ":")) return {ScriptFailure::Kind::kError, "script " + message + " (in " + function + ")"};
  return {ScriptFailure::Kind::kError, where + ": " + message + " (in " + function + ")"};
}

}  // namespace orcs::script
