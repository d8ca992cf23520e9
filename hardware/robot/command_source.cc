#include "hardware/robot/command_source.h"

#include <cmath>

#include "model/control/controller_factory.h"
#include "model/core/error.h"
#include "model/scene/scenario.h"
#include "model/scene/simulation.h"

namespace orcs::hardware {

void RecordSource::Commands(double time, const std::vector<double>&, std::vector<double>& goal,
                            std::vector<double>& torque) {
  const control::Keyframe* frame = &record_.frames.front();
  for (const control::Keyframe& candidate : record_.frames) {
    if (candidate.time_ms > time * 1000.0 + 1e-9) break;
    frame = &candidate;
  }
  for (std::size_t j = 0; j < goal.size(); ++j) {
    goal[j] = frame->inputs[2 * j];
    torque[j] = std::abs(frame->inputs[2 * j + 1]);
  }
}

ControllerSource::ControllerSource(const std::string& scenario, const nlohmann::json* genome, double duration,
                                   SimulatedTwin& twin, const JointMap& map)
    : twin_(twin) {
  const scene::Scenario parsed = scene::ParseScenario(scene::ResolveScenarioFile(scenario), scenario);
  if (parsed.agent != map.agent) {
    throw InputError(scenario, 0, "the scenario drives agent '" + parsed.agent + "', the joint map " + map.source +
                                      " agent '" + map.agent + "'");
  }
  const nlohmann::json& chosen = genome ? *genome : parsed.genome;
  scene::Simulation& simulation = twin_.simulation();
  control::ControlTarget target{map.agent, simulation.agent(twin_.agent_index()).motor_names()};
  controller_ = control::MakeController(parsed.controller, chosen.is_null() ? nlohmann::json::array() : chosen,
                                        target, simulation, twin_.agent_index(), scenario);
  duration_ = duration > 0 ? duration : parsed.duration;
}

ControllerSource::~ControllerSource() = default;

void ControllerSource::Commands(double time, const std::vector<double>& measured, std::vector<double>& goal,
                                std::vector<double>& torque) {
  twin_.SetJointSensors(measured);
  controller_->Update(time);
  twin_.Inputs(goal, torque);
  for (double& t : torque) t = std::abs(t);
}

}  // namespace orcs::hardware
