// Run-time physics parameters: the per-run context of a world (Drake's Context), not part of its structure.
// The scene layer fills this from the repository (/Simulation/..., /MaterialProperties/...) whenever those
// values change, so a value file, a job or the OSP gateway can change them between or during runs.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "model/physics/material_table.h"

namespace orcs::physics {

/// Which ODE stepper integrates the world.
enum class Solver {
  kWorldStep,  ///< exact "big matrix" solver, dWorldStep (the original's choice)
  kQuickStep,  ///< iterative solver, dWorldQuickStep, with `quickstep_iterations`
};

/// MuJoCo's constraint solver (mjtSolver).
enum class MujocoSolver { kPGS, kCG, kNewton };

/// The MuJoCo engine's solver settings, /Simulation/MuJoCo/... (docs/model.md, "The MuJoCo backend"); ODE
/// ignores them. The defaults are MuJoCo's own except where docs/benchmarks.md measured a faster choice of
/// the same accuracy.
struct MujocoSettings {
  MujocoSolver solver = MujocoSolver::kNewton;  ///< /Simulation/MuJoCo/Solver (only "Newton" offered: docs/model.md)
  int iterations = 100;                         ///< most solver iterations per step, /Simulation/MuJoCo/Iterations
  double tolerance = 1e-8;                      ///< relative cost decrease that ends the solve, -, .../Tolerance
  bool implicit_integrator = false;             ///< .../Integrator: "Euler" or "Implicit" (in velocity)
  bool elliptic_cone = false;                   ///< .../Cone: "Pyramidal" or "Elliptic" friction cones
  double contact_time_constant = 0.02;          ///< s, contact softness: solref[0], .../ContactTimeConstant
  double contact_damping_ratio = 1.0;           ///< -, solref[1], /Simulation/MuJoCo/ContactDampingRatio
};

struct PhysicsParameters {
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};  ///< m/s², /Simulation/Gravitation (magnitude along −y)
  double erp = 0.2;                   ///< world error reduction parameter, -, /Simulation/ODE/ERP
  double cfm = 1e-5;                  ///< world constraint force mixing, -, /Simulation/ODE/ConstraintForceMixing
  Solver solver = Solver::kWorldStep;  ///< /Simulation/ODE/Solver ("WorldStep" | "QuickStep")
  int quickstep_iterations = 20;      ///< iterations of kQuickStep, /Simulation/ODE/QuickStepIterations
  double contact_surface_layer = 0.001;  ///< m of allowed penetration, /Simulation/ODE/ContactSurfaceLayer
  double contact_max_correcting_velocity = std::numeric_limits<double>::infinity();  ///< m/s
  int max_contact_points = 100;       ///< per geom pair, 1..kMaxContactPoints, /Simulation/ODE/MaxContactPoints
  double soft_erp = 0.2;              ///< contact ERP, /Simulation/ODE/SoftERP
  double soft_cfm = 1e-5;             ///< contact CFM, /Simulation/ODE/SoftCFM
  double contact_slip = 0.001;        ///< force-dependent slip in both friction directions, (m/s)/N
  double min_bouncing_velocity = 0.0;  ///< m/s below which contacts do not bounce
  double friction_scaling = 1.0;      ///< factor on the dynamic friction coefficient only, -
  /// Relative tangential speed below which a contact uses the static coefficient, m/s
  /// (/Simulation/ODE/StaticFrictionSpeed). The original meant "static when not sliding" but read an unset
  /// field; this is the documented rule that replaces it (docs/model.md).
  double static_friction_speed = 0.01;
  /// kWorldStep only: solve a motorised hinge's angular motor and friction brake as one constraint row whenever
  /// the last step shows which of the two is at its torque limit, and check after the step that it was (else the
  /// step is redone with both rows). The same constraint problem, solved about twice as fast for the A-Series;
  /// results differ from two rows by rounding only (docs/model.md, "Motor and brake rows"). false: always two rows.
  bool combine_motor_rows = true;
  double min_contact_depth = 1e-6;    ///< contact points shallower than this are dropped, m
  double max_linear_speed = 1e3;      ///< a body faster than this makes the step unstable, m/s
  double max_angular_speed = 1e4;     ///< a body spinning faster than this makes the step unstable, rad/s
  MujocoSettings mujoco;              ///< /Simulation/MuJoCo/...: the MuJoCo engine's solver
  CustomMaterial custom1;             ///< /MaterialProperties/Custom1/...
  CustomMaterial custom2;             ///< /MaterialProperties/Custom2/...

  static constexpr int kMaxContactPoints = 100;  ///< size of the per-pair contact buffer
};

}  // namespace orcs::physics
