// The physical servo model (docs/model.md, "The physical servo"): a motor mode beside the original's velocity
// servo, for fitting real Dynamixel data. The servo's firmware computes a PWM duty from the position error with
// its register gains (P, I, D), clipped to its PWM limit; the H-bridge puts duty × supply voltage on a DC motor
// whose torque at the output is kt·(V·duty − ke·ω)/R; the gear train adds its reflected rotor inertia (armature)
// and Coulomb and viscous friction. The further gearbox effects (Stribeck, load-dependent, back-driving, LuGre,
// backlash, delay) are the effect catalogue's (motor_effects.h) and combine with it.
//
// The DC motor is applied as an angular motor with an implicit compliance (PhysicsWorld::SetJointMotorCompliance):
// a motor row with target velocity V·duty/ke and compliance R/(kt·ke) yields τ = kt·(V·duty − ke·ω')/R at the
// step's end rate ω', which stays stable where an explicit back-EMF torque would not (kt·ke/R·dt/I ≫ 1 on the
// A-Series' light limbs). Pure computation like dynamixel_motor.h: no engine, no repository, no allocation.
#pragma once

#include <array>

#include "model/aseries/dynamixel_motor.h"
#include "model/aseries/parameter_table.h"

namespace orcs::aseries {

/// The servo's parameters, shared by all motors. Defaults: the AX-12+ (scenarios/values/servo_ax12.val says
/// where each number comes from); the XL330-M288 is scenarios/values/servo_xl330.val.
struct ServoParameters {
  bool enabled = false;            ///< the motor mode: true = this model, false = the original's, /Servo/Enabled
  /// The firmware's position P gain in its register's units, /Servo/FirmwareKp. An input of the run (the gain the
  /// servo was set to), never a fitted parameter: orcs-gap takes it from the measured run.
  double firmware_kp = 0.03125;
  double firmware_ki = 0.0;        ///< I gain, register units, /Servo/FirmwareKi (0 = none)
  double firmware_kd = 0.0;        ///< D gain, register units, /Servo/FirmwareKd (0 = none)
  double kp_scale = 195.569;       ///< duty per rad of error per unit of FirmwareKp, /Servo/KpScale
  double ki_scale = 0.0;           ///< duty per rad·s of integrated error per unit of FirmwareKi, /Servo/KiScale
  double kd_scale = 0.0;           ///< duty per rad/s of error rate per unit of FirmwareKd, /Servo/KdScale
  double pwm_limit = 1.0;          ///< largest |duty|, 0…1 (the PWM limit register over its maximum), /Servo/PwmLimit
  double supply_voltage = 12.0;    ///< V across the H-bridge, /Servo/SupplyVoltage
  /// A, the firmware's bound on the winding current, |τ| ≤ kt·limit (the X series' Current Limit register;
  /// the AX-12+ has none), /Servo/CurrentLimit; 0 = none
  double current_limit = 0.0;
  double torque_constant = 1.0;    ///< kt, N·m per A at the output (gear ratio included), /Servo/TorqueConstant
  double resistance = 8.0;         ///< R, Ω of the winding at ReferenceTemperature, /Servo/Resistance
  /// °C of the winding during the run, /Servo/WindingTemperature. An input of the run like FirmwareKp: orcs-gap
  /// takes it from the measured run when the data has it; otherwise it is the reference and R is as given.
  double winding_temperature = 25.0;
  double reference_temperature = 25.0;  ///< °C at which Resistance holds, /Servo/ReferenceTemperature
  /// 1/K, the winding resistance's rise per kelvin (copper: 0.00393), /Servo/ResistanceTemperatureCoefficient
  double resistance_temperature_coefficient = 0.00393;
  double back_emf_constant = 1.94;  ///< ke, V per rad/s of the output, /Servo/BackEmfConstant
  double armature = 0.0016;        ///< kg·m², the rotor's inertia reflected to the output, /Servo/Armature
  double coulomb_friction = 0.05;  ///< N·m, the gearbox's friction at any speed, /Servo/CoulombFriction
  double viscous_friction = 0.02;  ///< N·m·s/rad, the gearbox's friction per speed, /Servo/ViscousFriction
};

/// Which motor model runs, one switch for every motor (it has no per-motor copy: per_motor_parameters.h).
inline constexpr std::string_view kServoEnabledPath = "/Servo/Enabled";

inline constexpr std::array<ParameterField<ServoParameters>, 19> kServoParameterTable{{
    {"/Servo/Enabled", &ServoParameters::enabled},
    {"/Servo/FirmwareKp", &ServoParameters::firmware_kp},
    {"/Servo/FirmwareKi", &ServoParameters::firmware_ki},
    {"/Servo/FirmwareKd", &ServoParameters::firmware_kd},
    {"/Servo/KpScale", &ServoParameters::kp_scale},
    {"/Servo/KiScale", &ServoParameters::ki_scale},
    {"/Servo/KdScale", &ServoParameters::kd_scale},
    {"/Servo/PwmLimit", &ServoParameters::pwm_limit},
    {"/Servo/SupplyVoltage", &ServoParameters::supply_voltage},
    {"/Servo/CurrentLimit", &ServoParameters::current_limit},
    {"/Servo/TorqueConstant", &ServoParameters::torque_constant},
    {"/Servo/Resistance", &ServoParameters::resistance},
    {"/Servo/WindingTemperature", &ServoParameters::winding_temperature},
    {"/Servo/ReferenceTemperature", &ServoParameters::reference_temperature},
    {"/Servo/ResistanceTemperatureCoefficient", &ServoParameters::resistance_temperature_coefficient},
    {"/Servo/BackEmfConstant", &ServoParameters::back_emf_constant},
    {"/Servo/Armature", &ServoParameters::armature},
    {"/Servo/CoulombFriction", &ServoParameters::coulomb_friction},
    {"/Servo/ViscousFriction", &ServoParameters::viscous_friction},
}};

/// What the engine applies in servo mode.
struct ServoCommand {
  DynamixelCommand motor;   ///< target velocity V·duty/ke (rad/s), torque bound (N·m), gearbox friction (N·m)
  double compliance = 0.0;  ///< R/(kt·ke), rad/s per N·m: the motor row yields like the DC motor; 0 = limp
  double duty = 0.0;        ///< the PWM duty, −1…1 (0 when limp)
  double torque = 0.0;      ///< N·m, the motor's torque kt·(V·duty − ke·ω)/R at the step's start rate; 0 = limp
};

/// The winding's resistance at its temperature, Ω: R·(1 + α·(T − T_ref)), never below a tiny positive value. A
/// warm servo is weaker: copper's α is 0.393 % per kelvin.
double WindingResistance(const ServoParameters& servo);

/// The motor's torque at full duty and rest, kt·V/R (R at the winding's temperature), N·m.
double StallTorque(const ServoParameters& servo);

/// The PWM duty the firmware commands for a position error (rad), its integral (rad·s) and rate (rad/s), clipped
/// to ±PwmLimit·clamp(desired_torque, 0, 1).
double ServoDuty(const ServoParameters& servo, double error, double error_integral, double error_rate,
                 double desired_torque_raw);

/// One servo step: `angle_rad` and `rate` are the joint's, `desired_angle_deg` the goal (clamped to ±150°),
/// `desired_torque_raw` the torque enable and limit: ≤ 0 (or NaN) is a limp servo — no motor torque, the
/// windings open, only the gearbox's friction — and 0…1 scales the PWM limit (the AX-12+'s torque limit, the
/// XL330's goal PWM). Keeps the error integral and the last error in `state` (an integral that cannot raise the
/// duty further does not grow: no wind-up).
ServoCommand ServoUpdate(const ServoParameters& servo, DynamixelState& state, double angle_rad, double rate,
                         double desired_angle_deg, double desired_torque_raw, double dt);

}  // namespace orcs::aseries
