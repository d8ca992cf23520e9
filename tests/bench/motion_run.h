// One motion record of scenarios/motions/ played on one engine through scene::Simulation, as `orcs-sim -play`
// does (the player's Apply before every step): what the engine benchmark times and the engine trace comparison
// runs.
#pragma once

#include <cmath>
#include <memory>
#include <string>

#include "model/control/keyframe_player.h"
#include "model/control/keyframe_record.h"
#include "model/scene/environment_reader.h"
#include "model/scene/simulation.h"

namespace orcs::bench {

struct Motion {
  const char* name;
  const char* environment;  ///< below the source tree; "" = the default A-Series on the floor
  const char* record;       ///< below the source tree; "" = no input
  double seconds = 0;       ///< episode length, simulated s; 0 = the record's length
  const char* agent = "Humanoid";  ///< the agent the record drives
};

inline std::string SourcePath(const std::string& relative) { return std::string(ORCS_SOURCE_DIR) + "/" + relative; }

// One motion on one engine through scene::Simulation as a batch job runs it, the record played before each step.
class MotionRun {
 public:
  MotionRun(const Motion& motion, const std::string& engine) : agent_name_(motion.agent) {
    scene::EnvironmentDescription environment;
    if (*motion.environment) {
      environment = scene::EnvironmentReader::ReadFile(SourcePath(motion.environment));
    } else {
      environment.agents.push_back(scene::AgentDescription{});
    }
    simulation_.repository().Set("/Simulation/Engine", engine);
    simulation_.LoadEnvironment(environment);
    simulation_.Build();
    simulation_.SetExcludedCollisionEvents(false);  // as a batch job runs it (model/evaluation)
    const aseries::ASeriesAgent& agent = this->agent();
    steps_ = static_cast<int>(std::lround(motion.seconds / simulation_.StepDuration()));
    if (*motion.record) {
      record_ = control::ReadKeyframeRecord(SourcePath(motion.record), agent.motor_count());
      player_ = std::make_unique<control::KeyframePlayer>(record_, agent_name_, agent.motor_names(),
                                                          simulation_.repository());
      steps_ = static_cast<int>(std::lround(record_.frames.back().time_ms / 1000.0 / simulation_.StepDuration()));
    }
  }

  int steps() const { return steps_; }
  scene::Simulation& simulation() { return simulation_; }
  aseries::ASeriesAgent& agent() { return simulation_.agent(simulation_.FindAgent(agent_name_)); }

  // One episode; `after_step` sees the simulation after every step. False if the run failed.
  template <typename AfterStep>
  bool Episode(AfterStep&& after_step) {
    for (int i = 0; i < steps_; ++i) {
      if (player_) player_->Apply(simulation_.time());
      if (simulation_.Step() != scene::SimulationStatus::kOk) return false;
      after_step(i);
    }
    return true;
  }

 private:
  std::string agent_name_;
  scene::Simulation simulation_;
  control::KeyframeRecord record_;
  std::unique_ptr<control::KeyframePlayer> player_;
  int steps_ = 0;
};

}  // namespace orcs::bench
