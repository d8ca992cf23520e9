// The sandbox scripts run in (model/script/script_sandbox.h): what a hostile script meets — no files, processes,
// code loading; a budget no pcall can catch; a memory cap; one-line messages — and what keeps a script's bits fixed.
#include "model/script/script_sandbox.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <lua.hpp>
#include <string>

#include "model/core/error.h"

namespace orcs::script {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

// Small limits, so that a hostile script reaches them at once.
ScriptLimits Small() {
  ScriptLimits limits;
  limits.instructions = 1'000'000;
  limits.memory_bytes = std::size_t{8} << 20;
  return limits;
}

// The failure running `text` as "hostile.lua" throws; fails the test when it runs to the end.
ScriptFailure FailureOf(const std::string& text, const ScriptLimits& limits = Small()) {
  ScriptSandbox sandbox("hostile.lua", limits);
  try {
    sandbox.Run(text);
  } catch (const ScriptFailure& failure) {
    return failure;
  }
  ADD_FAILURE() << "the script ran to its end: " << text;
  return {ScriptFailure::Kind::kError, ""};
}

// The global `name` after running `text`, as text (numbers as Lua prints them).
std::string GlobalAfter(const std::string& text, std::uint64_t seed = 1) {
  ScriptSandbox sandbox("ok.lua", Small());
  sandbox.StartSet(seed);
  sandbox.Run(text);
  lua_getglobal(sandbox.state(), "result");
  std::size_t length = 0;
  const char* value = lua_tolstring(sandbox.state(), -1, &length);
  return value == nullptr ? "(nil)" : std::string(value, length);
}

TEST(ScriptSandboxTest, OrdinaryLuaRuns) {
  EXPECT_EQ(GlobalAfter("local t = {} for i = 1, 10 do t[#t + 1] = i * i end result = table.concat(t, ',')"),
            "1,4,9,16,25,36,49,64,81,100");
  EXPECT_EQ(GlobalAfter("result = string.format('%.3f %s', math.sqrt(2), 'x')"), "1.414 x");
  // pcall and xpcall as in Lua, for everything but a limit
  EXPECT_EQ(GlobalAfter("local ok, a, b = pcall(function(x) return x, 8 end, 7)\n"
                        "local bad, e = pcall(error, 'oops', 0)\n"
                        "local h, m = xpcall(function() error('deep', 0) end, function(m) return 'handled ' .. m end)\n"
                        "result = table.concat({tostring(ok), a, b, tostring(bad), e, tostring(h), m}, ' ')"),
            "true 7 8 false oops false handled deep");
}

TEST(ScriptSandboxTest, ProcessesFilesAndModulesAreRefusedByName) {
  for (const auto& [text, name] : {std::pair{"os.execute('touch /tmp/pwned')", "os.execute"},
                                   {"io.open('/etc/passwd')", "io.open"},
                                   {"require('socket')", "require"},
                                   {"dofile('/etc/passwd')", "dofile"},
                                   {"debug.sethook()", "debug.sethook"},
                                   {"local x = os.time()", "os.time"},
                                   {"load('return 1')", "load"},
                                   {"package.loadlib('x', 'y')", "package.loadlib"}}) {
    const ScriptFailure failure = FailureOf(text);
    EXPECT_EQ(failure.kind(), ScriptFailure::Kind::kError) << text;
    EXPECT_THAT(failure.what(), AllOf(HasSubstr("hostile.lua:1:"), HasSubstr(std::string(name) + " is not available")))
        << text;
  }
}

TEST(ScriptSandboxTest, BytecodeCanNeitherBeMadeNorLoaded) {
  EXPECT_THAT(FailureOf("local f = load(string.dump(function() return 1 end))").what(),
              HasSubstr("string.dump is not available"));
  ScriptSandbox sandbox("compiled.lua", Small());
  try {
    sandbox.Run(std::string(LUA_SIGNATURE) + "T");
    ADD_FAILURE() << "a binary chunk ran";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("compiled.lua: is a compiled Lua chunk"));
  }
}

TEST(ScriptSandboxTest, AnEndlessLoopReachesTheBudgetAndNoPcallCatchesIt) {
  const ScriptFailure loop = FailureOf("local x = 0\nwhile true do\n  x = x + 1\nend");
  EXPECT_EQ(loop.kind(), ScriptFailure::Kind::kLimit);
  EXPECT_THAT(loop.what(), AllOf(HasSubstr("script 'hostile.lua' line 3"), HasSubstr("instruction budget of 1000000")));
  const ScriptFailure caught = FailureOf(
      "while true do\n  pcall(function() while true do end end)\n  xpcall(function() while true do end end, print)\nend");
  EXPECT_EQ(caught.kind(), ScriptFailure::Kind::kLimit);
}

TEST(ScriptSandboxTest, AHugeTableReachesTheMemoryCapAndNoPcallCatchesIt) {
  const ScriptFailure table = FailureOf("local t = {}\nfor i = 1, 1e10 do t[i] = i end");  // 10 GB and more
  EXPECT_EQ(table.kind(), ScriptFailure::Kind::kLimit);
  EXPECT_THAT(table.what(), AllOf(HasSubstr("line 2"), HasSubstr("memory cap of 8 MiB")));
  const ScriptFailure caught =
      FailureOf("while true do pcall(function() local s = string.rep('x', 1 << 30) end) end");
  EXPECT_EQ(caught.kind(), ScriptFailure::Kind::kLimit);
  EXPECT_THAT(caught.what(), HasSubstr("memory cap"));
}

TEST(ScriptSandboxTest, DeepRecursionIsAnErrorWithItsLine) {
  const ScriptFailure failure = FailureOf("local function f(n)\n  return 1 + f(n + 1)\nend\nf(1)",
                                          ScriptLimits{100'000'000, std::size_t{64} << 20});
  EXPECT_EQ(failure.kind(), ScriptFailure::Kind::kError);
  EXPECT_THAT(failure.what(), AllOf(HasSubstr("hostile.lua:2:"), HasSubstr("stack overflow")));
}

TEST(ScriptSandboxTest, AHugeErrorMessageArrivesAsOneShortLine) {
  const ScriptFailure failure = FailureOf("error(string.rep('spam\\n', 200000))");
  const std::string what = failure.what();
  EXPECT_EQ(failure.kind(), ScriptFailure::Kind::kError);
  EXPECT_LT(what.size(), 400u);
  EXPECT_EQ(what.find('\n'), std::string::npos);
  EXPECT_THAT(what, AllOf(HasSubstr("hostile.lua:1: spam spam"), HasSubstr("...")));
  EXPECT_THAT(FailureOf("error({})").what(), HasSubstr("an error value that is not text"));
}

TEST(ScriptSandboxTest, LoopsInsideOneLibraryCallAreRefusedOrBounded) {
  EXPECT_EQ(GlobalAfter("result = '[' .. string.rep('', 1e15) .. ']'"), "[]");  // returns at once
  EXPECT_THAT(FailureOf("table.move({}, 1, 1e15, 2)").what(), HasSubstr("table.move is not available"));
  EXPECT_THAT(FailureOf("string.find(string.rep('a', 1e5), '.-.-.-.-b')").what(),
              HasSubstr("string.find is not available"));
}

TEST(ScriptSandboxTest, ASyntaxErrorNamesTheScriptAndLine) {
  ScriptSandbox sandbox("typo.lua", Small());
  try {
    sandbox.Run("function finish()\n  return 1 +\nend");
    ADD_FAILURE() << "a syntax error ran";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("script typo.lua:3:"));
  }
  EXPECT_THROW(ScriptSandbox::CheckSyntax("typo.lua", "x = = 1"), InputError);
  EXPECT_NO_THROW(ScriptSandbox::CheckSyntax("ok.lua", "x = 1"));
}

// pairs visits keys in a fixed order (numbers, then strings), whatever the process's string hash seed.
TEST(ScriptSandboxTest, PairsVisitsKeysInAFixedOrder) {
  EXPECT_EQ(GlobalAfter("local t = {zeta = 1, alpha = 2, [3] = 3, [1.5] = 4, mid = 5, [-2] = 6}\n"
                        "local keys = {} for k in pairs(t) do keys[#keys + 1] = tostring(k) end\n"
                        "result = table.concat(keys, ' ')"),
            "-2 1.5 3 alpha mid zeta");
  EXPECT_THAT(FailureOf("for k in pairs({[{}] = 1}) do end").what(), HasSubstr("has no fixed order"));
  EXPECT_THAT(FailureOf("next({})").what(), HasSubstr("next is not available"));
}

TEST(ScriptSandboxTest, RandomNumbersComeFromTheSetsSeed) {
  const std::string draw = "result = string.format('%.17g %d', math.random(), math.random(1, 1000000))";
  EXPECT_EQ(GlobalAfter(draw, 7), GlobalAfter(draw, 7));
  EXPECT_NE(GlobalAfter(draw, 7), GlobalAfter(draw, 8));
  EXPECT_THAT(FailureOf("math.randomseed(42)").what(), HasSubstr("math.randomseed is not available"));
}

TEST(ScriptSandboxTest, NoTextShowsAnAddress) {
  EXPECT_EQ(GlobalAfter("result = tostring({}) .. ' ' .. tostring(print)"), "table function");
  EXPECT_EQ(GlobalAfter("result = string.format('%s|%5s', {}, 'x')"), "table|    x");
  EXPECT_THAT(FailureOf("local s = string.format('%p', {})").what(), HasSubstr("%p (an address) is not available"));
}

TEST(ScriptSandboxTest, FunctionsAreCalledByReferenceAndTheirErrorsNameThem) {
  ScriptSandbox sandbox("calls.lua", Small());
  sandbox.Run("count = 0\nfunction step(dt) count = count + dt end\nfunction bad() local t = nil; return t.x end");
  const int step = sandbox.FunctionRef("step");
  ASSERT_GE(step, 0);
  EXPECT_LT(sandbox.FunctionRef("missing"), 0);
  for (int i = 0; i < 3; ++i) {
    lua_pushnumber(sandbox.state(), 0.5);
    sandbox.Call(step, "step", 1, 0);
  }
  lua_getglobal(sandbox.state(), "count");
  EXPECT_EQ(lua_tonumber(sandbox.state(), -1), 1.5);
  lua_pop(sandbox.state(), 1);
  try {
    sandbox.Call(sandbox.FunctionRef("bad"), "bad", 0, 0);
    ADD_FAILURE() << "bad() returned";
  } catch (const ScriptFailure& failure) {
    EXPECT_THAT(failure.what(), AllOf(HasSubstr("calls.lua:3:"), HasSubstr("(in bad)"), Not(HasSubstr("\n"))));
  }
}

// The budget is per parameter set: StartSet gives it back.
TEST(ScriptSandboxTest, EachSetHasTheWholeBudget) {
  ScriptSandbox sandbox("sets.lua", Small());
  sandbox.Run("function work() local x = 0 for i = 1, 200000 do x = x + i end end");  // ~400,000 instructions
  const int work = sandbox.FunctionRef("work");
  for (int set = 0; set < 5; ++set) {
    sandbox.StartSet(static_cast<std::uint64_t>(set));
    sandbox.Call(work, "work", 0, 0);
    sandbox.Call(work, "work", 0, 0);
  }
  sandbox.StartSet(9);
  EXPECT_THROW(for (int i = 0; i < 3; ++i) sandbox.Call(work, "work", 0, 0), ScriptFailure);
}

}  // namespace
}  // namespace orcs::script
