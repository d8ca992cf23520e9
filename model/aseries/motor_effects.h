// The motor effects (docs/gap.md): switchable physical extensions of the Dynamixel motor model that the
// original's model lacks, each off by default and controlled by repository values under /Effects/<Name>/...,
// so that a model fitted by orcs-gap is just a value file. Pure computation like dynamixel_motor.h: the caller
// keeps one MotorEffectState per motor and calls ApplyEffects around the base controller step. What orcs-gap fits
// of each effect, and in which range, is its catalogue (model/identify/effect_catalogue.h).
//
//   TransportDelay  the command reaches the motor `Delay` s late (linear interpolation between steps)
//   DeadBand        the controller ignores position errors within ±`Margin` (the AX-12's compliance margin)
//   BackEmf         the torque limit falls linearly with speed, to 0 at `NoLoadSpeed`
//   Stribeck        extra friction `BreakawayTorque`·exp(−(ω/`Velocity`)²) that vanishes once the joint moves
//   LoadFriction    extra friction `Coefficient`·|motor torque|: a gearbox whose friction grows with its load
//   GravityLoadFriction  extra friction `Coefficient`·|τg − τ|, τg gravity's torque on the load the joint turns and
//                   τ the motor's (both in the joint angle's sense): the gear mesh carries the load's pull against
//                   the motor's, twice the torque of a hold (BAM's load-dependent model, M3, Duclusaud et al. 2024)
//   GearEfficiency  friction `Coefficient`·|τ| + q·τ² with q = `Curvature`·(1 − `Coefficient`)/(2·τs), τ the motor's
//                   torque and τs its largest (the servo's stall torque, the original's FMaxFactor): a gear train
//                   whose efficiency falls as its load grows. Curvature 0…1 keeps the output torque τ − friction
//                   growing with τ all the way to τs (at 1 it levels off there): friction never eats the motor
//   BackDrive       extra friction `Coefficient`·|motor torque| while the load drives the gear train backwards
//                   (the joint turns against the motor's torque; at rest, the direction it last moved decides):
//                   a worm-like gearbox that is harder to back-drive than to drive
//   Backlash        the output turns freely within a gap of `Width` between the gear and the output (a tooth pushes,
//                   never pulls: the gap is crossed when the load changes sign)
//   Elasticity      the gear train is a torsional spring `Stiffness` with damper `Damping` between motor and output
//   RotorInertia    the motor's rotor, reflected through the gearbox, adds `Inertia` about the joint axis
//   LuGre           friction of elastic bristles (Canudas de Wit et al. 1995): a bristle deflection z with
//                   dz/dt = ω − σ0·|ω|·z/g(ω), g(ω) = Fc + (Fs − Fc)·exp(−(ω/vs)²), gives the friction
//                   |σ0·z + σ1·dz/dt| (`BristleStiffness` σ0, `BristleDamping` σ1, `CoulombTorque` Fc,
//                   `StictionTorque` Fs, `StribeckVelocity` vs): it holds up to Fs at rest, follows the Stribeck
//                   curve when sliding, and lags behind a change of speed (frictional memory). Applied as the
//                   brake, which holds rigidly: the presliding creep of a turn of load/σ0 is not reproduced.
#pragma once

#include <array>
#include <vector>

#include "model/aseries/dynamixel_motor.h"
#include "model/aseries/parameter_table.h"
#include "model/aseries/servo_motor.h"

namespace orcs::aseries {

/// Every effect's switch and parameters; all off by default (the original's model).
struct MotorEffects {
  bool transport_delay = false;  ///< /Effects/TransportDelay/Enabled
  double delay = 0.0;            ///< s, command to motor, /Effects/TransportDelay/Delay
  bool dead_band = false;        ///< /Effects/DeadBand/Enabled
  double margin = 0.0;           ///< degrees, half-width of the ignored error band, /Effects/DeadBand/Margin
  bool back_emf = false;         ///< /Effects/BackEmf/Enabled
  double no_load_speed = 1e9;    ///< rad/s where the available torque reaches 0, /Effects/BackEmf/NoLoadSpeed
  bool stribeck = false;         ///< /Effects/Stribeck/Enabled
  double breakaway_torque = 0.0;  ///< N·m extra friction at rest, /Effects/Stribeck/BreakawayTorque
  double stribeck_velocity = 0.1;  ///< rad/s over which it fades, /Effects/Stribeck/Velocity
  bool load_friction = false;    ///< /Effects/LoadFriction/Enabled
  double load_coefficient = 0.0;  ///< N·m of friction per N·m of motor torque, /Effects/LoadFriction/Coefficient
  bool gravity_load_friction = false;  ///< /Effects/GravityLoadFriction/Enabled
  double gravity_load_coefficient = 0.0;  ///< N·m of friction per N·m of |τg − τ|, /Effects/GravityLoadFriction/Coefficient
  bool gear_efficiency = false;  ///< /Effects/GearEfficiency/Enabled
  double efficiency_coefficient = 0.0;  ///< μ, N·m of friction per N·m of motor torque, /Effects/GearEfficiency/Coefficient
  double efficiency_curvature = 0.0;    ///< q's share of its largest monotone value, 0…1, /Effects/GearEfficiency/Curvature
  bool back_drive = false;       ///< /Effects/BackDrive/Enabled
  double back_drive_coefficient = 0.0;  ///< N·m of friction per N·m of motor torque, back-driven, /Effects/BackDrive/Coefficient
  bool backlash = false;         ///< /Effects/Backlash/Enabled
  double backlash_width = 0.0;   ///< degrees, full width of the gap, /Effects/Backlash/Width
  bool elasticity = false;       ///< /Effects/Elasticity/Enabled
  double stiffness = 1e9;        ///< N·m/rad of the gear train, /Effects/Elasticity/Stiffness
  double damping = 0.02;         ///< N·m·s/rad across the spring, /Effects/Elasticity/Damping
  bool rotor_inertia = false;    ///< /Effects/RotorInertia/Enabled
  double inertia = 0.0;          ///< kg·m² about the joint axis, /Effects/RotorInertia/Inertia
  bool lugre = false;            ///< /Effects/LuGre/Enabled
  double bristle_stiffness = 100.0;  ///< σ0, N·m/rad of bristle deflection, /Effects/LuGre/BristleStiffness
  double bristle_damping = 0.1;      ///< σ1, N·m·s/rad on the deflection's rate, /Effects/LuGre/BristleDamping
  double coulomb_torque = 0.0;       ///< Fc, N·m of sliding friction, /Effects/LuGre/CoulombTorque
  double stiction_torque = 0.0;      ///< Fs, N·m the bristles hold at rest, /Effects/LuGre/StictionTorque
  double lugre_velocity = 0.1;       ///< vs, rad/s over which Fs falls to Fc, /Effects/LuGre/StribeckVelocity

  /// Whether any effect is on (the agent skips ApplyEffects otherwise, keeping the original's bits).
  bool any() const;
};

inline constexpr std::array<ParameterField<MotorEffects>, 31> kMotorEffectsTable{{
    {"/Effects/TransportDelay/Enabled", &MotorEffects::transport_delay},
    {"/Effects/TransportDelay/Delay", &MotorEffects::delay},
    {"/Effects/DeadBand/Enabled", &MotorEffects::dead_band},
    {"/Effects/DeadBand/Margin", &MotorEffects::margin},
    {"/Effects/BackEmf/Enabled", &MotorEffects::back_emf},
    {"/Effects/BackEmf/NoLoadSpeed", &MotorEffects::no_load_speed},
    {"/Effects/Stribeck/Enabled", &MotorEffects::stribeck},
    {"/Effects/Stribeck/BreakawayTorque", &MotorEffects::breakaway_torque},
    {"/Effects/Stribeck/Velocity", &MotorEffects::stribeck_velocity},
    {"/Effects/LoadFriction/Enabled", &MotorEffects::load_friction},
    {"/Effects/LoadFriction/Coefficient", &MotorEffects::load_coefficient},
    {"/Effects/GravityLoadFriction/Enabled", &MotorEffects::gravity_load_friction},
    {"/Effects/GravityLoadFriction/Coefficient", &MotorEffects::gravity_load_coefficient},
    {"/Effects/GearEfficiency/Enabled", &MotorEffects::gear_efficiency},
    {"/Effects/GearEfficiency/Coefficient", &MotorEffects::efficiency_coefficient},
    {"/Effects/GearEfficiency/Curvature", &MotorEffects::efficiency_curvature},
    {"/Effects/BackDrive/Enabled", &MotorEffects::back_drive},
    {"/Effects/BackDrive/Coefficient", &MotorEffects::back_drive_coefficient},
    {"/Effects/Backlash/Enabled", &MotorEffects::backlash},
    {"/Effects/Backlash/Width", &MotorEffects::backlash_width},
    {"/Effects/Elasticity/Enabled", &MotorEffects::elasticity},
    {"/Effects/Elasticity/Stiffness", &MotorEffects::stiffness},
    {"/Effects/Elasticity/Damping", &MotorEffects::damping},
    {"/Effects/RotorInertia/Enabled", &MotorEffects::rotor_inertia},
    {"/Effects/RotorInertia/Inertia", &MotorEffects::inertia},
    {"/Effects/LuGre/Enabled", &MotorEffects::lugre},
    {"/Effects/LuGre/BristleStiffness", &MotorEffects::bristle_stiffness},
    {"/Effects/LuGre/BristleDamping", &MotorEffects::bristle_damping},
    {"/Effects/LuGre/CoulombTorque", &MotorEffects::coulomb_torque},
    {"/Effects/LuGre/StictionTorque", &MotorEffects::stiction_torque},
    {"/Effects/LuGre/StribeckVelocity", &MotorEffects::lugre_velocity},
}};

/// What the motor stage knows about a joint before the step.
struct JointReading {
  double angle = 0.0;         ///< rad, joint (output) angle
  double rate = 0.0;          ///< rad/s, joint rate
  double motor_torque = 0.0;  ///< N·m the motor applied in the last step
  /// N·m gravity exerts on the load the joint turns (the bodies beyond it from the robot's root), in the joint
  /// angle's sense; computed only while GravityLoadFriction is on, else 0.
  double gravity_torque = 0.0;
};

/// The memory the effects need per motor. Reset it with ResetEffects at every simulation reset.
struct MotorEffectState {
  static constexpr int kHistory = 256;     ///< commands remembered: the longest delay is kHistory − 2 steps
  std::array<double, kHistory> angle_history{};   ///< desired angles, degrees, ring (newest at next − 1)
  std::array<double, kHistory> torque_history{};  ///< desired torques, raw, ring
  int history_next = 0;     ///< where the next command goes
  int history_count = 0;    ///< commands stored so far (≤ kHistory)
  double gear_angle = 0.0;  ///< rad, the motor side of the backlash gap / of the spring
  bool engaged = true;      ///< backlash: the gap was closed in the last step
  int wall = 0;             ///< backlash: the wall the gear pushed in the last step, +1 upper, −1 lower, 0 none
  double spring_angle = 0.0;  ///< rad, motor-side angle of the elastic gear train
  double bristle = 0.0;       ///< rad, LuGre's bristle deflection z
  bool resting = true;        ///< LuGre: the joint was at rest in the last step (its bristles held the load)
  bool back_driven = false;   ///< BackDrive: the joint last moved against the motor's torque
};

/// GearEfficiency's friction (N·m) at motor torque `torque` (N·m) for a motor whose largest torque is `stall`.
double GearEfficiencyFriction(const MotorEffects& effects, double torque, double stall);

/// LuGre's friction torque (N·m, ≥ 0, applied as the brake) for a step of `dt` s at joint rate `rate` (rad/s). At
/// rest it is the stiction Fs; the first moving step starts from bristles loaded to Fs in the direction of motion
/// (the load broke them away), and the deflection then advances exactly over each step for its constant rate.
double LuGreFriction(const MotorEffects& effects, double rate, double dt, MotorEffectState& state);

/// What the engine applies: the base command, possibly made compliant (elasticity).
struct EffectCommand {
  DynamixelCommand motor;   ///< velocity, torque limit, friction
  double compliance = 0.0;  ///< rad/s per N·m for PhysicsWorld::SetJointMotorCompliance; 0 = stiff
};

/// Clears the effect memory; `angle_rad` is the joint angle at the reset.
void ResetEffects(MotorEffectState& state, double angle_rad);

/// One motor step with the effects: delays and dead-bands the command, runs the base controller (Update, or
/// ServoUpdate when `servo.enabled`), then shapes its torque limit, friction, backlash gap and compliance. With
/// every effect off it returns the base controller's command unchanged. Elasticity needs the motor row's
/// compliance, which the servo mode's DC motor takes: the caller refuses the two together
/// (CheckEffectsFitServo).
EffectCommand UpdateWithEffects(const DynamixelParameters& parameters, const ServoParameters& servo,
                                const MotorEffects& effects, DynamixelState& state, MotorEffectState& effect_state, const JointReading& joint,
                                double desired_angle_deg, double desired_torque_raw, double dt, RandomStream* noise);

/// Throws InputError when the effects cannot combine with the motor mode: Elasticity with /Servo/Enabled.
void CheckEffectsFitServo(const ServoParameters& servo, const MotorEffects& effects);

}  // namespace orcs::aseries
