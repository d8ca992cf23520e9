#include "model/fitness/script_term.h"

#include <cmath>
#include <lua.hpp>

#include "model/core/error.h"

namespace orcs::fitness {

ScriptTerm::ScriptTerm(const script::ScriptSpec& spec, const scene::Simulation& simulation, int agent_index)
    : api_(simulation, agent_index, nullptr),
      sandbox_(std::make_unique<script::ScriptSandbox>(spec.name, spec.limits)) {
  api_.Open(*sandbox_);
  script::SetGlobal(*sandbox_, "params", spec.params);
  sandbox_->Run(spec.text);
  start_ = sandbox_->FunctionRef("start");
  step_ = sandbox_->FunctionRef("step");
  stop_ = sandbox_->FunctionRef("stop");
  finish_ = sandbox_->FunctionRef("finish");
  if (finish_ < 0) {
    throw InputError(spec.name, 0, "a fitness script defines function finish(), which returns the term's value");
  }
}

void ScriptTerm::Start(const scene::Simulation& simulation) {
  sandbox_->StartSet(simulation.seed());
  stopped_ = false;
  value_.reset();
  if (start_ >= 0) sandbox_->Call(start_, "start", 0, 0);
}

void ScriptTerm::Sample(const scene::Simulation&, double dt) {
  lua_State* state = sandbox_->state();
  if (step_ >= 0) {
    lua_pushnumber(state, dt);
    sandbox_->Call(step_, "step", 1, 0);
  }
  if (stop_ >= 0) {
    sandbox_->Call(stop_, "stop", 0, 1);
    stopped_ = lua_toboolean(state, -1) != 0;
    lua_pop(state, 1);
  }
}

double ScriptTerm::value() const {
  if (value_) return *value_;
  lua_State* state = sandbox_->state();
  sandbox_->Call(finish_, "finish", 0, 1);
  const bool number = lua_type(state, -1) == LUA_TNUMBER;
  const double result = lua_tonumber(state, -1);
  const char* type = luaL_typename(state, -1);
  lua_pop(state, 1);
  if (!number || !std::isfinite(result)) {
    throw script::ScriptFailure(script::ScriptFailure::Kind::kError,
                                "script '" + sandbox_->name() + "': finish() expected to return a finite number, found " +
                                    (number ? std::to_string(result) : std::string("a ") + type));
  }
  value_ = result;
  return result;
}

}  // namespace orcs::fitness
