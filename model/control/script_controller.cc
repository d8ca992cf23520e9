#include "model/control/script_controller.h"

#include <lua.hpp>

#include "model/core/error.h"

namespace orcs::control {

ScriptController::ScriptController(const script::ScriptSpec& spec, const std::vector<double>& genome,
                                   scene::Simulation& simulation, int agent_index)
    : simulation_(simulation),
      api_(simulation, agent_index, &simulation.repository()),
      sandbox_(std::make_unique<script::ScriptSandbox>(spec.name, spec.limits)) {
  api_.Open(*sandbox_);
  script::SetGlobal(*sandbox_, "params", spec.params);
  script::SetGlobal(*sandbox_, "genome", nlohmann::json(genome));
  sandbox_->Run(spec.text);
  reset_ = sandbox_->FunctionRef("reset");
  control_ = sandbox_->FunctionRef("control");
  if (control_ < 0) {
    throw InputError(spec.name, 0, "a controller script defines function control(t), which sets the motors");
  }
}

void ScriptController::Reset() {
  sandbox_->StartSet(simulation_.seed());
  if (reset_ >= 0) sandbox_->Call(reset_, "reset", 0, 0);
}

void ScriptController::Update(double time_seconds) {
  lua_pushnumber(sandbox_->state(), time_seconds);
  sandbox_->Call(control_, "control", 1, 0);
}

}  // namespace orcs::control
