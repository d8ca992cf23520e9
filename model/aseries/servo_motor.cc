#include "model/aseries/servo_motor.h"

#include <algorithm>
#include <cmath>

#include "base/demand.h"
#include "model/aseries/value_range.h"
#include "model/core/rotation.h"

namespace orcs::aseries {
namespace {

// Guards the divisions by R, kt and ke against zero values in a value file.
constexpr double kTiny = 1e-9;

double DutyLimit(const ServoParameters& servo, double desired_torque_raw) {
  if (std::isnan(desired_torque_raw)) return 0.0;
  return std::clamp(servo.pwm_limit, 0.0, 1.0) * std::clamp(desired_torque_raw, 0.0, 1.0);
}

}  // namespace

double WindingResistance(const ServoParameters& servo) {
  const double warming =
      servo.resistance_temperature_coefficient * (servo.winding_temperature - servo.reference_temperature);
  return std::max(servo.resistance * (1.0 + warming), kTiny);
}

double StallTorque(const ServoParameters& servo) {
  return std::max(servo.torque_constant, kTiny) * std::max(servo.supply_voltage, 0.0) / WindingResistance(servo);
}

double ServoDuty(const ServoParameters& servo, double error, double error_integral, double error_rate,
                 double desired_torque_raw) {
  const double limit = DutyLimit(servo, desired_torque_raw);
  const double duty = servo.firmware_kp * servo.kp_scale * error + servo.firmware_ki * servo.ki_scale * error_integral +
                      servo.firmware_kd * servo.kd_scale * error_rate;
  return std::clamp(duty, -limit, limit);
}

ServoCommand ServoUpdate(const ServoParameters& servo, DynamixelState& state, double angle_rad, double rate,
                         double desired_angle_deg, double desired_torque_raw, double dt) {
  ORCS_DEMAND(dt > 0.0);
  const double resistance = WindingResistance(servo);
  const double kt = std::max(servo.torque_constant, kTiny);
  const double ke = std::max(servo.back_emf_constant, kTiny);
  const double friction = std::max(servo.coulomb_friction, 0.0) + std::max(servo.viscous_friction, 0.0) * std::abs(rate);

  // 1. Firmware: the position error, its rate and integral, the duty. The first step after a reset has no rate.
  const double error = DegreesToRadians(kDesiredAngleRange.ClampRaw(desired_angle_deg)) - angle_rad;
  const double error_rate = state.history_count == 0 ? 0.0 : (error - state.previous_error) / dt;
  const double integral = state.error_integral + error * dt;
  const double duty = ServoDuty(servo, error, integral, error_rate, desired_torque_raw);
  // No wind-up: the integral only grows while the duty is not at its limit.
  if (std::abs(duty) < DutyLimit(servo, desired_torque_raw)) state.error_integral = integral;
  state.previous_error = error;
  state.previous_angle = angle_rad;
  state.history_count = 1;

  ServoCommand command;
  command.motor.friction_torque = friction;
  if (DutyLimit(servo, desired_torque_raw) <= 0.0) {  // limp: torque off, windings open
    state.velocity = 0.0;
    state.max_torque = 0.0;
    command.motor.velocity = 0.0;
    command.motor.max_torque = 0.0;
    return command;
  }
  // 2. H-bridge and DC motor: τ = kt·(V·duty − ke·ω')/R as a compliant velocity motor. The bound only keeps the
  // row finite; it is twice what the motor can give at this speed, so it never binds in a step.
  const double voltage = std::max(servo.supply_voltage, 0.0);
  command.duty = duty;
  command.motor.velocity = voltage * duty / ke;
  command.compliance = resistance / (kt * ke);
  command.motor.max_torque = kt / resistance * (voltage + 2.0 * ke * std::abs(rate));
  command.torque = kt / resistance * (voltage * duty - ke * rate);
  // 3. The firmware's current limit: the row's bound is then the motor's torque at that current.
  if (servo.current_limit > 0.0) {
    const double limit = kt * servo.current_limit;
    command.motor.max_torque = std::min(command.motor.max_torque, limit);
    command.torque = std::clamp(command.torque, -limit, limit);
  }
  state.velocity = command.motor.velocity;
  state.max_torque = command.motor.max_torque;
  return command;
}

}  // namespace orcs::aseries
