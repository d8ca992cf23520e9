// What changes when a user switches /Simulation/Engine: every motion record of scenarios/motions/ played on ODE and
// on MuJoCo, the traces compared step by step. Per motion: the head's position difference (max and RMS over the
// steps, mm) and the joint angle difference (max and RMS over the steps and all motors, degrees), as the table in
// docs/benchmarks.md. Not timed; deterministic (both engines give the same bits on every run).
//
//   engine_traces
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/bench/motion_run.h"

namespace orcs::bench {
namespace {

const Motion kMotions[] = {
    {"waist_bend", "", "scenarios/motions/waist_bend.csv"},
    {"leg_swing", "scenarios/environments/leg_swing.xml", "scenarios/motions/leg_swing.csv"},
    {"arm_movement", "", "scenarios/motions/arm_movement.csv"},
    // The A-Series example's identification motions (docs/gap.md): diagnosed on MuJoCo, made on ODE.
    {"aseries_identification_a", "", "scenarios/motions/aseries_identification_a.csv"},
    {"aseries_identification_b", "", "scenarios/motions/aseries_identification_b.csv"},
    {"arm_swings", "", "scenarios/motions/arm_swings.csv"},
    {"sit_up", "scenarios/environments/lying_on_back.xml", "scenarios/motions/sit_up.csv"},
    {"stand_up", "scenarios/environments/lying_on_back.xml", "scenarios/motions/stand_up.csv"},
    {"pendulum_steps", "scenarios/environments/pendulum.xml", "scenarios/motions/pendulum_steps.csv", 0, "Pendulum"},
};

struct Trace {
  std::vector<Eigen::Vector3d> head;         ///< per step, m (empty for an agent without a head)
  std::vector<std::vector<double>> angles;   ///< per step, per motor, degrees (noise-free, from the physics)
  std::string status = "ok";
};

Trace Play(const Motion& motion, const std::string& engine) {
  MotionRun run(motion, engine);
  scene::Simulation& simulation = run.simulation();
  const physics::PhysicsModel& model = *simulation.model().physics();
  const int head = model.FindBody(std::string(motion.agent) + "/Middle/Head");
  std::vector<int> joints;
  for (const std::string& motor : run.agent().motor_names()) {
    joints.push_back(model.FindJoint(std::string(motion.agent) + "/" + motor));
  }
  Trace trace;
  const bool ok = run.Episode([&](int) {
    if (head >= 0) trace.head.push_back(simulation.physics().body_state(head).position);
    std::vector<double>& angles = trace.angles.emplace_back();
    for (int joint : joints) angles.push_back(simulation.physics().joint_angle(joint) * 180.0 / M_PI);
  });
  if (!ok) trace.status = simulation.message();
  return trace;
}

struct Difference {
  double max = 0.0, sum_of_squares = 0.0;
  long count = 0;
  void Add(double d) {
    max = std::max(max, std::abs(d));
    sum_of_squares += d * d;
    ++count;
  }
  double rms() const { return count ? std::sqrt(sum_of_squares / static_cast<double>(count)) : 0.0; }
};

void Compare(const Motion& motion) {
  const Trace ode = Play(motion, "ODE"), mujoco = Play(motion, "MuJoCo");
  Difference head, angle;
  for (size_t i = 0; i < std::min(ode.head.size(), mujoco.head.size()); ++i) {
    head.Add((ode.head[i] - mujoco.head[i]).norm() * 1e3);
  }
  for (size_t i = 0; i < std::min(ode.angles.size(), mujoco.angles.size()); ++i) {
    for (size_t k = 0; k < ode.angles[i].size(); ++k) angle.Add(ode.angles[i][k] - mujoco.angles[i][k]);
  }
  const std::string head_text = head.count ? std::to_string(head.max).substr(0, 5) + " | " +
                                                 std::to_string(head.rms()).substr(0, 5)
                                           : "– | –";
  std::printf("| %s | %zu | %s | %.3f | %.3f | %s / %s |\n", motion.name, ode.angles.size(), head_text.c_str(),
              angle.max, angle.rms(), ode.status.c_str(), mujoco.status.c_str());
}

}  // namespace
}  // namespace orcs::bench

int main() {
  std::printf("| motion | steps | head max (mm) | head RMS (mm) | joint max (°) | joint RMS (°) | status ODE / MuJoCo |\n"
              "|---|---|---|---|---|---|---|\n");
  for (const orcs::bench::Motion& motion : orcs::bench::kMotions) orcs::bench::Compare(motion);
}
