// The sandboxed script engine jobs carry (docs/extending.md): one Lua 5.4 state per script per parameter set, with
// only what a fitness term or a controller needs — no files, processes, clocks, network or loading of code — and
// bounded: an instruction budget per parameter set and a memory cap, past which the script fails with
// ScriptFailure::Kind::kLimit, naming the limit and the script's line. Deterministic: no clock, the random stream
// is orcs's own (seeded by the parameter set), `pairs` visits keys in a fixed order, and nothing prints an address.
//
// Lua reports errors by longjmp, so the functions this file gives Lua never hold a C++ object with a destructor
// while they may raise one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "model/core/random_stream.h"

struct lua_State;
struct lua_Debug;

namespace orcs::script {

/// What one script may use (scenario "limits": {"instructions": N, "memory_mib": M}).
struct ScriptLimits {
  /// Lua VM instructions per parameter set — the top level, every call of every function together. The default
  /// (2·10⁸) is about a second of a busy script; a fitness term of a few lines per step of a 10 s run uses 10⁵.
  std::int64_t instructions = 200'000'000;
  /// Bytes the script's state may hold at once (64 MiB).
  std::size_t memory_bytes = std::size_t{64} << 20;
};
inline constexpr std::int64_t kMaxScriptInstructions = 100'000'000'000;  ///< the largest budget a scenario may set
inline constexpr std::size_t kMaxScriptMemoryBytes = std::size_t{1} << 30;  ///< the largest cap a scenario may set (1 GiB)

/// A script failed while it ran: an error it raised or made (kError), or a limit it reached (kLimit). what() is one
/// line: "script 'head_level.lua' line 12: attempt to index a nil value (global 'os')".
class ScriptFailure : public std::runtime_error {
 public:
  enum class Kind { kError, kLimit };
  ScriptFailure(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

class ScriptSandbox {
 public:
  /// A state for the script `name` (a file name, for messages) with the sandbox's libraries; the caller adds its
  /// own globals (the `orcs` table, `params`) and then Runs the script.
  ScriptSandbox(std::string name, const ScriptLimits& limits);
  ~ScriptSandbox();
  ScriptSandbox(const ScriptSandbox&) = delete;
  ScriptSandbox& operator=(const ScriptSandbox&) = delete;

  /// Compiles `text` (Lua 5.4 source; a binary chunk is refused) and runs its top level. Throws InputError
  /// "script name:line: message" for a syntax error and ScriptFailure for an error or a limit while it runs.
  void Run(const std::string& text);
  /// Compiles `text` as the script `name` without running it: InputError for a syntax error, as Run throws.
  static void CheckSyntax(const std::string& name, const std::string& text);

  lua_State* state() const { return state_; }
  const std::string& name() const { return name_; }

  /// A registry reference to the global function `function`, or −1 (LUA_NOREF) when the script defines none.
  /// Throws ScriptFailure when the global holds something else than a function.
  int FunctionRef(const char* function) const;
  /// Calls the function `ref` (FunctionRef) with the `arguments` values the caller pushed, leaving `results`
  /// values on the stack. Throws ScriptFailure naming `function` on an error or a limit.
  void Call(int ref, const char* function, int arguments, int results);
  /// Calls the function below the `arguments` values on top of the stack, as Call does (`what` names it).
  void CallStack(int arguments, int results, const char* what);

  /// A new parameter set: the instruction budget starts again and the random stream (math.random, orcs.random) is
  /// the set's own, from `seed`.
  void StartSet(std::uint64_t seed);
  /// The random stream scripts draw from.
  RandomStream& random() { return random_; }

  /// Instructions used in this parameter set so far (counted in slices of the hook's interval).
  std::int64_t instructions_used() const { return used_; }

  /// The sandbox a Lua state belongs to (stored in the state's extra space).
  static ScriptSandbox& Of(lua_State* state);

 private:
  static void* Allocate(void* self, void* block, std::size_t old_size, std::size_t new_size);
  static void CountHook(lua_State* state, lua_Debug* where);
  static int ProtectedCall(lua_State* state);
  static int ProtectedCallWithHandler(lua_State* state);
  // pcall's results with the call's values from index 2 on: a limit raised again (no script may catch one), else
  // the status as a boolean at index 1 and everything above it.
  static int PcallResults(lua_State* state, int status);
  void OpenLibraries();
  void Compile(const std::string& text);  // leaves the compiled chunk on the stack
  // The message of a failed call (status, error value on top of the stack), one line, bounded; pops the value.
  ScriptFailure FailureOf(int status, const char* function);

  std::string name_;
  ScriptLimits limits_;
  lua_State* state_ = nullptr;
  std::size_t bytes_ = 0;          ///< bytes the state holds now
  std::int64_t used_ = 0;          ///< instructions used in this set
  bool over_budget_ = false;       ///< the instruction budget ran out: every further hook raises again
  bool out_of_memory_ = false;     ///< an allocation was refused by the cap and the script saw the error
  int limit_line_ = 0;             ///< the script's line when the budget ran out
  int memory_line_ = 0;            ///< the script's line when the cap last refused a block
  RandomStream random_{0, "script"};
};

}  // namespace orcs::script
