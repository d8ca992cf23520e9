// Steps per CPU-second of the A-Series on the two engines, in one process (issue 20): orcs on ODE, orcs on MuJoCo,
// and raw MuJoCo — mj_step1 / mj_step2 on the model orcs exports (--export-mjcf), no orcs code in the loop.
// Three motions: standing 10 s without input, the leg swing (scenarios/motions/leg_swing.csv on its rig) and the
// arm movement (arm_movement.csv). Targets: orcs-MuJoCo ≥ 7× orcs-ODE and ≥ 0.9× raw MuJoCo on each motion.
//
// The orcs sides play the record as `orcs-sim -play` does: the whole Dynamixel motor model, sensors, repository
// values and events. Raw MuJoCo has none of these. Each hinge's motor is what orcs's MuJoCo world makes of it: the
// tendon's friction-loss row (full torque) aimed at a target velocity by shifting its reference acceleration
// between mj_step1 and mj_step2. The target velocity takes the joint in one step to where the orcs-MuJoCo run had
// it at that step; that joint trajectory is recorded once before timing. Contacts keep the exported geoms'
// friction (orcs rewrites it per contact from the material table). So raw MuJoCo solves the same constraint
// problem on the same model, and the ratio is what orcs's layer and models cost. Before timing, the program
// prints how far the raw robot's head ends from orcs-MuJoCo's.
//
// Each iteration is one episode from a reset; the reset is outside the timing.
//
//   engine_bench --benchmark_repetitions=5 --benchmark_min_time=2 --benchmark_report_aggregates_only=true
//                --benchmark_enable_random_interleaving=true
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/physics/mujoco/mjcf_export.h"
#include "model/scene/simulation.h"
#include "tests/bench/motion_run.h"
#include "tests/bench/rate_reporter.h"

namespace orcs::bench {
namespace {

constexpr const char* kAgent = "Humanoid";
constexpr const char* kHead = "Humanoid/Middle/Head";

const Motion kMotions[] = {
    {"stand", "", "", 10.0},
    {"leg_swing", "scenarios/environments/leg_swing.xml", "scenarios/motions/leg_swing.csv"},
    {"arm_movement", "", "scenarios/motions/arm_movement.csv"},
};
constexpr const char* kEngines[] = {"ODE", "MuJoCo"};

// The same robot in raw MuJoCo, driven along a recorded joint trajectory.
class RawMujocoRun {
 public:
  // `trajectory[i][k]`: hinge k's angle after step i, rad; `hinges`: the hinges' names (MJCF joint names).
  RawMujocoRun(const std::string& mjcf, std::vector<std::string> hinges, std::vector<std::vector<double>> trajectory,
               double dt)
      : trajectory_(std::move(trajectory)), dt_(dt) {
    char error[1000] = "";
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    mj_makeEmptyFileVFS(&vfs, "orcs.xml", static_cast<int>(mjcf.size()));
    std::copy(mjcf.begin(), mjcf.end(), static_cast<char*>(vfs.filedata[vfs.nfile - 1]));
    m_ = mj_loadXML("orcs.xml", &vfs, error, sizeof error);
    mj_deleteVFS(&vfs);
    if (!m_) throw std::runtime_error(std::string("raw MuJoCo cannot load the exported model: ") + error);
    d_ = mj_makeData(m_);
    m_->opt.timestep = dt;
    for (const std::string& hinge : hinges) {
      qpos_.push_back(m_->jnt_qposadr[mj_name2id(m_, mjOBJ_JOINT, hinge.c_str())]);
      tendon_.push_back(mj_name2id(m_, mjOBJ_TENDON, ("motor:" + hinge).c_str()));
    }
    target_.assign(m_->ntendon, 0.0);
    head_ = mj_name2id(m_, mjOBJ_BODY, kHead);
  }
  ~RawMujocoRun() {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  RawMujocoRun(const RawMujocoRun&) = delete;
  RawMujocoRun& operator=(const RawMujocoRun&) = delete;

  void Reset() {
    mj_resetData(m_, d_);
    for (int t : tendon_) m_->tendon_frictionloss[t] = kFullTorque;
  }

  int steps() const { return static_cast<int>(trajectory_.size()); }
  double head_height() const { return d_->xpos[3 * head_ + 1]; }

  void Step(int i) {
    for (size_t k = 0; k < tendon_.size(); ++k) {
      target_[tendon_[k]] = (trajectory_[i][k] - d_->qpos[qpos_[k]]) / dt_;
    }
    mj_step1(m_, d_);
    for (int row = 0; row < d_->nefc; ++row) {
      if (d_->efc_type[row] == mjCNSTR_FRICTION_TENDON) {
        d_->efc_aref[row] += d_->efc_KBIP[4 * row + 1] * target_[d_->efc_id[row]];
      }
    }
    mj_step2(m_, d_);
  }

 private:
  static constexpr double kFullTorque = 1.05;  // N·m, the AX-12+'s torque limit at full DesiredTorque
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<std::vector<double>> trajectory_;
  double dt_;
  std::vector<int> qpos_, tendon_;
  std::vector<double> target_;
  int head_ = -1;
};

// Runs the motion once on orcs-MuJoCo and returns the raw-MuJoCo run that follows its joints.
std::unique_ptr<RawMujocoRun> MakeRawRun(const Motion& motion, double* orcs_head) {
  MotionRun orcs(motion, "MuJoCo");
  scene::Simulation& simulation = orcs.simulation();
  const physics::PhysicsModel& model = *simulation.model().physics();
  std::vector<std::string> hinges;
  std::vector<int> joints;
  for (const std::string& motor : simulation.agent(simulation.FindAgent(kAgent)).motor_names()) {
    hinges.push_back(std::string(kAgent) + "/" + motor);
    joints.push_back(model.FindJoint(hinges.back()));
  }
  std::vector<std::vector<double>> trajectory;
  orcs.Episode([&](int) {
    std::vector<double>& angles = trajectory.emplace_back();
    for (int joint : joints) angles.push_back(simulation.physics().joint_angle(joint));
  });
  *orcs_head = simulation.physics().body_state(model.FindBody(kHead)).position.y();
  return std::make_unique<RawMujocoRun>(physics::ExportMjcf(model, {.exclusions = true}), hinges, trajectory, simulation.StepDuration());
}

void BM_Orcs(benchmark::State& state, const Motion& motion, const std::string& engine) {
  MotionRun run(motion, engine);
  for (auto _ : state) {
    state.PauseTiming();
    run.simulation().Reset(0);
    state.ResumeTiming();
    if (!run.Episode([](int) {})) state.SkipWithError(run.simulation().message().c_str());
  }
  state.SetItemsProcessed(state.iterations() * run.steps());
}

void BM_RawMujoco(benchmark::State& state, const Motion& motion) {
  double orcs_head = 0.0;
  const std::unique_ptr<RawMujocoRun> run = MakeRawRun(motion, &orcs_head);
  for (auto _ : state) {
    state.PauseTiming();
    run->Reset();
    state.ResumeTiming();
    for (int i = 0; i < run->steps(); ++i) run->Step(i);
  }
  state.SetItemsProcessed(state.iterations() * run->steps());
}

// The raw robot must do what orcs-MuJoCo did, or the comparison means nothing: the head's end height, both sides.
void PrintRawCheck() {
  for (const Motion& motion : kMotions) {
    double orcs_head = 0.0;
    const std::unique_ptr<RawMujocoRun> run = MakeRawRun(motion, &orcs_head);
    run->Reset();
    for (int i = 0; i < run->steps(); ++i) run->Step(i);
    std::printf("%-13s head at the end: orcs-MuJoCo %.4f m, raw MuJoCo %.4f m\n", motion.name, orcs_head,
                run->head_height());
  }
}

void RegisterBenchmarks() {
  for (const Motion& motion : kMotions) {
    for (const char* engine : kEngines) {
      benchmark::RegisterBenchmark((std::string("BM_Orcs") + engine + "/" + motion.name).c_str(), BM_Orcs, motion,
                                   std::string(engine))
          ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark((std::string("BM_RawMuJoCo/") + motion.name).c_str(), BM_RawMujoco, motion)
        ->Unit(benchmark::kMillisecond);
  }
}

void PrintSummary(const RateReporter& reporter) {
  std::printf("\n| motion | orcs-ODE steps/s | orcs-MuJoCo steps/s | raw MuJoCo steps/s | MuJoCo / ODE | "
              "orcs-MuJoCo / raw |\n|---|---|---|---|---|---|\n");
  for (const Motion& motion : kMotions) {
    const std::string name = motion.name;
    const double ode = reporter.Get("BM_OrcsODE/" + name), mujoco = reporter.Get("BM_OrcsMuJoCo/" + name),
                 raw = reporter.Get("BM_RawMuJoCo/" + name);
    if (ode <= 0 || mujoco <= 0 || raw <= 0) continue;
    std::printf("| %s | %.0f | %.0f | %.0f | %.2f× | %.2f× |\n", motion.name, ode, mujoco, raw, mujoco / ode,
                mujoco / raw);
  }
}

}  // namespace
}  // namespace orcs::bench

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  orcs::bench::PrintRawCheck();
  orcs::bench::RegisterBenchmarks();
  orcs::bench::RateReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  orcs::bench::PrintSummary(reporter);
  benchmark::Shutdown();
}
