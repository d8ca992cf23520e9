#include "model/aseries/dynamixel_motor.h"

#include <algorithm>
#include <cmath>

#include "base/demand.h"
#include "model/aseries/value_range.h"
#include "model/core/random_stream.h"
#include "model/core/rotation.h"

namespace orcs::aseries {

void Reset(DynamixelState& state, double angle_rad) {
  state.error_history.fill(0.0);
  state.history_next = 0;
  state.history_count = 0;
  state.previous_angle = angle_rad;
  state.previous_error = 0.0;
  state.max_torque = 0.0;
  state.velocity = 0.0;
  state.error_integral = 0.0;
}

double TorqueLimit(const DynamixelParameters& parameters, double desired_torque_raw) {
  const double torque = kDesiredTorqueRange.ClampRaw(desired_torque_raw);
  if (std::isnan(torque)) return 0.0;  // no command is no torque
  return parameters.fmax_factor * (parameters.torque_control ? std::abs(torque) : std::max(0.0, torque));
}

double SuccessorFriction(const DynamixelParameters& parameters, double measured_velocity) {
  const double speed = std::abs(measured_velocity);
  return std::max(0.0, (speed < parameters.static_friction_border ? parameters.static_friction : 0.0) +
                           parameters.dynamic_friction * speed + parameters.dynamic_friction_offset);
}

double OriginalFriction(const DynamixelParameters& parameters, double commanded_velocity) {
  // Literally f = fs + αd·v + od for |v| ≤ bs (and without fs above it): signed, not floored. The floor
  // below is the engine's, made explicit: a hinge motor with FMax ≤ 0 adds no force.
  const double f = (std::abs(commanded_velocity) <= parameters.static_friction_border ? parameters.static_friction
                                                                                       : 0.0) +
                   parameters.dynamic_friction * commanded_velocity + parameters.dynamic_friction_offset;
  return std::max(0.0, f);
}

DynamixelCommand Update(const DynamixelParameters& parameters, DynamixelState& state, double angle_rad,
                        double desired_angle_deg, double desired_torque_raw, double dt, RandomStream* noise) {
  ORCS_DEMAND(dt > 0.0);
  constexpr int kCapacity = DynamixelParameters::kMaxHistory;

  // 1–2. Joint angle and its finite-difference velocity (no wrap-around case: within ±150° angles never wrap).
  const double angle = angle_rad;
  const double angular_velocity = (angle - state.previous_angle) / dt;

  // 3. Desired angle, clamped to the interface range, in radians. Under torque control the goal is the end of the
  // range the torque points to, so that the motor pushes with its torque limit (as on the real AX-12+).
  const double goal_deg = parameters.torque_control ? std::copysign(kDesiredAngleRange.raw_max, desired_torque_raw)
                                                    : kDesiredAngleRange.ClampRaw(desired_angle_deg);
  const double desired_angle = DegreesToRadians(goal_deg);

  // 4. PID. The history behaves like the original's list of the last HistorySize errors: append, then drop
  // the oldest until at most HistorySize remain (so a smaller HistorySize takes effect at once, a larger one
  // fills up over the following steps).
  const double error = desired_angle - angle;
  state.error_history[state.history_next] = error;
  state.history_next = (state.history_next + 1) % kCapacity;
  const int history_size = std::clamp(parameters.history_size, 1, kCapacity);
  state.history_count = std::min(state.history_count + 1, history_size);
  double error_sum = 0.0;  // oldest to newest
  for (int i = state.history_count; i >= 1; --i) {
    error_sum += state.error_history[(state.history_next - i + kCapacity) % kCapacity];
  }
  const double integral_part = std::abs(parameters.ki) < 1e-10 ? 0.0 : dt / parameters.ki * error_sum;
  const double differential_part = parameters.kd / dt * (error - state.previous_error);
  double velocity = parameters.kp * (error + integral_part + differential_part);

  // 5. Clip the commanded velocity (not the error).
  if (parameters.max_velocity >= 0.0) {
    velocity = std::clamp(velocity, -parameters.max_velocity, parameters.max_velocity);
  }

  // 6. Friction brake on the hinge, in the successor's form or the original's.
  const double friction = parameters.original_friction ? OriginalFriction(parameters, velocity)
                                                       : SuccessorFriction(parameters, angular_velocity);

  // 7. Motor noise, after the clip as in the original.
  if (parameters.include_noise && parameters.motor_noise > 0.0 && noise != nullptr) {
    velocity += noise->Normal(0.0, parameters.motor_noise);
  }

  // 8–9. Command, and remember what the next step needs. The torque limit follows DesiredTorque and
  // FMaxFactor every step (§6c, decided in docs/model.md, "Torque limit (quirk 6)").
  state.previous_angle = angle;
  state.previous_error = error;
  state.max_torque = TorqueLimit(parameters, desired_torque_raw);
  state.velocity = velocity;
  return DynamixelCommand{velocity, state.max_torque, friction};
}

}  // namespace orcs::aseries
