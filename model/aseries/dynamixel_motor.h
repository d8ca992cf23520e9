// The Dynamixel AX-12+ motor model of the A-Series (spec/aseries.md §6): a PID position controller that
// commands the target velocity of an angular motor, a torque limit from the desired torque, and a friction
// brake on the hinge. Pure computation, no physics engine and no repository: the caller fills
// DynamixelParameters from the repository (kDynamixelParameterTable), keeps one DynamixelState per motor,
// calls Update before every physics step with the joint angle, and applies the returned command to the
// engine (AMotor target velocity and FMax, hinge friction FMax with target velocity 0). No allocation.
// Decisions on the original's quirks: docs/model.md, "The Dynamixel motor and the A-Series sensors: decisions".
#pragma once

#include <array>
#include <string_view>

#include "model/aseries/parameter_table.h"

namespace orcs {
class RandomStream;
}

namespace orcs::aseries {

/// The global motor parameters, shared by all motors. Defaults: Set A (spec §6e), the effective one.
struct DynamixelParameters {
  double kp = 20.0;  ///< proportional gain, 1/s (v = Kp·(e + I + D)), /AngularMotor/PID/Proportional
  double ki = 0.0;   ///< integral divisor, s (I = dt/Ki · Σ last errors), |Ki| < 1e-10 = off, /AngularMotor/PID/Integral
  double kd = 0.0;   ///< differential time, s (D = Kd/dt · (e − e_prev)), /AngularMotor/PID/Differential
  int history_size = 10;          ///< errors summed by the I-part, 1..kMaxHistory, /AngularMotor/PID/HistorySize
  double fmax_factor = 1.04803939;  ///< N·m per unit of raw DesiredTorque, /AngularMotor/FMaxFactor
  double max_velocity = 3.5;      ///< |commanded velocity| limit, rad/s, < 0 = no limit, /AngularMotor/MaxVelocity
  double static_friction = 0.001;         ///< fs, N·m, /AngularMotor/StaticFriction
  double static_friction_border = 0.1;    ///< bs, rad/s below which fs acts, /AngularMotor/StaticFrictionBorder
  double dynamic_friction = 0.16;         ///< αd, N·m·s/rad, /AngularMotor/DynamicFriction
  double dynamic_friction_offset = 0.0;   ///< od, N·m, /AngularMotor/DynamicFrictionOffset
  double motor_noise = 0.0;       ///< σ of the noise on the commanded velocity, rad/s, /AngularMotor/MotorNoise
  bool include_noise = true;      ///< motor and angle-sensor noise switch, /AngularMotor/IncludeNoise
  /// Friction form, /AngularMotor/OriginalFriction. false (default): the successor's (NERD), from the measured
  /// speed |ω|: f = max(0, fs·[|ω| < bs] + αd·|ω| + od). true: the original's (ORCS 1.0) as its manual wrote
  /// it, from the commanded velocity v (signed): f = fs·[|v| ≤ bs] + αd·v + od, where a negative f brakes
  /// nothing (an ODE hinge motor with FMax ≤ 0 applies no force). docs/model.md, "Differences", item 6.
  bool original_friction = false;
  /// Motor mode, /AngularMotor/TorqueControl. false (default): position control, DesiredAngle is the goal and
  /// DesiredTorque (−1…1, only its positive part) the torque limit. true: the original's torque-guided control of
  /// the AX-12+ — DesiredTorque is a signed torque command: the goal is the end of the range in its direction
  /// (+150° or −150°) and the torque limit FMaxFactor·|DesiredTorque|; DesiredAngle is not used.
  bool torque_control = false;

  static constexpr int kMaxHistory = 64;  ///< capacity of the error history; history_size is clamped to it
};

/// Repository paths of every DynamixelParameters field, for AddParameters/ReadParameters.
inline constexpr std::array<ParameterField<DynamixelParameters>, 14> kDynamixelParameterTable{{
    {"/AngularMotor/PID/Proportional", &DynamixelParameters::kp},
    {"/AngularMotor/PID/Integral", &DynamixelParameters::ki},
    {"/AngularMotor/PID/Differential", &DynamixelParameters::kd},
    {"/AngularMotor/PID/HistorySize", &DynamixelParameters::history_size},
    {"/AngularMotor/FMaxFactor", &DynamixelParameters::fmax_factor},
    {"/AngularMotor/MaxVelocity", &DynamixelParameters::max_velocity},
    {"/AngularMotor/StaticFriction", &DynamixelParameters::static_friction},
    {"/AngularMotor/StaticFrictionBorder", &DynamixelParameters::static_friction_border},
    {"/AngularMotor/DynamicFriction", &DynamixelParameters::dynamic_friction},
    {"/AngularMotor/DynamicFrictionOffset", &DynamixelParameters::dynamic_friction_offset},
    {"/AngularMotor/MotorNoise", &DynamixelParameters::motor_noise},
    {"/AngularMotor/IncludeNoise", &DynamixelParameters::include_noise},
    {"/AngularMotor/OriginalFriction", &DynamixelParameters::original_friction},
    {"/AngularMotor/TorqueControl", &DynamixelParameters::torque_control},
}};

/// The memory of one motor's controller. Value-initialise it, then Reset it at every simulation reset.
struct DynamixelState {
  /// The last errors (rad), a ring: the newest is at index (history_next − 1) mod capacity.
  std::array<double, DynamixelParameters::kMaxHistory> error_history{};
  int history_next = 0;     ///< where the next error goes
  int history_count = 0;    ///< how many errors the I-part sums (≤ history size)
  double previous_angle = 0.0;  ///< θ_prev, rad
  double previous_error = 0.0;  ///< e_prev, rad
  double max_torque = 0.0;      ///< the last torque limit, N·m
  double velocity = 0.0;        ///< the last commanded velocity, rad/s (the repository's CurrentVelocity)
  double error_integral = 0.0;  ///< servo mode (servo_motor.h): the firmware's Σ error·dt, rad·s
};

/// What the engine has to apply before the physics step.
struct DynamixelCommand {
  double velocity;         ///< rad/s, angular-motor target velocity
  double max_torque;       ///< N·m, angular-motor FMax
  double friction_torque;  ///< N·m, hinge FMax with hinge target velocity 0 (a friction brake)
};

/// Clears the controller memory: empty error history, θ_prev = `angle_rad` (the joint angle at the reset,
/// 0 in the initial pose), e_prev = 0, no torque, no velocity.
void Reset(DynamixelState& state, double angle_rad = 0.0);

/// The angular motor's torque limit FMaxFactor × max(0, τ), N·m, with τ the raw DesiredTorque clamped to
/// −1…1 (under torque control FMaxFactor × |τ|). Update uses it every step; use it also for the AMotor FMax at
/// joint creation.
double TorqueLimit(const DynamixelParameters& parameters, double desired_torque_raw);

/// The successor's friction brake (N·m) for the measured joint velocity (rad/s), spec §6b step 6.
double SuccessorFriction(const DynamixelParameters& parameters, double measured_velocity);
/// The original's friction brake (N·m) for the commanded velocity v (rad/s, after the clip, before noise).
double OriginalFriction(const DynamixelParameters& parameters, double commanded_velocity);
/// One controller step (spec §6b steps 1–9, §6c): `angle_rad` is the current joint (AMotor) angle,
/// `desired_angle_deg` the raw DesiredAngle (clamped to ±150° here), `desired_torque_raw` the raw
/// DesiredTorque, `dt` > 0 the physics step in seconds. `noise` draws the motor noise; nullptr means none.
DynamixelCommand Update(const DynamixelParameters& parameters, DynamixelState& state, double angle_rad,
                        double desired_angle_deg, double desired_torque_raw, double dt, RandomStream* noise);

}  // namespace orcs::aseries
