#include "model/aseries/motor_effects.h"

#include <algorithm>
#include <cmath>

#include "base/demand.h"
#include "model/aseries/value_range.h"
#include "model/core/error.h"
#include "model/core/rotation.h"

namespace orcs::aseries {
namespace {

constexpr int kHistory = MotorEffectState::kHistory;

// The gap is closed when the gear side reaches a wall within this much (rad): the step's rounding must not open it.
constexpr double kWallTolerance = 1e-9;
// Below this joint rate (rad/s) the friction brake holds rather than slides: its torque may have either sign.
constexpr double kRestRate = 1e-6;

void PushCommand(MotorEffectState& state, double angle_deg, double torque_raw) {
  if (state.history_count == 0) {  // before the first command the motor has seen this one all along
    state.angle_history.fill(angle_deg);
    state.torque_history.fill(torque_raw);
  }
  state.angle_history[state.history_next] = angle_deg;
  state.torque_history[state.history_next] = torque_raw;
  state.history_next = (state.history_next + 1) % kHistory;
  state.history_count = std::min(state.history_count + 1, kHistory);
}

// The value `steps_back` steps before the newest (0 = newest), linear between stored steps.
double Delayed(const std::array<double, kHistory>& history, const MotorEffectState& state, double steps_back) {
  const double back = std::clamp(steps_back, 0.0, static_cast<double>(kHistory - 2));
  const int whole = static_cast<int>(back);
  const double fraction = back - whole;
  const auto at = [&](int k) { return history[(state.history_next - 1 - k + 2 * kHistory) % kHistory]; };
  return (1.0 - fraction) * at(whole) + fraction * at(whole + 1);
}

// The desired angle that gives the controller the dead-banded error: errors within ±margin count as none, larger
// ones lose the margin.
double DeadBandTarget(double angle_rad, double desired_deg, double margin_deg) {
  const double error = DegreesToRadians(kDesiredAngleRange.ClampRaw(desired_deg)) - angle_rad;
  const double reduced = std::copysign(std::max(0.0, std::abs(error) - DegreesToRadians(margin_deg)), error);
  return RadiansToDegrees(angle_rad + reduced);
}

// The motor side winds the spring at the controller's velocity, never further than its torque limit can hold;
// the compliant motor row then makes the spring implicit (PhysicsWorld::SetJointMotorCompliance). The limit
// applies to the wind-up the output has left after the last step (where the motor side stalled if the spring's
// torque reached the limit); within this step the motor row's torque limit caps the spring. Clamping after this
// step's wind-up instead, around the output's angle before the step, would let the output gain at most
// max_torque/(stiffness·dt) rad/s per step: a stiff gear train would freeze the joint rather than become the
// stiff motor.
void ApplyElasticity(const MotorEffects& effects, MotorEffectState& state, const JointReading& joint, double dt,
                     EffectCommand& command) {
  const double stiffness = std::max(effects.stiffness, 1e-9);
  const double damping = std::max(effects.damping, 0.0);
  const double velocity = command.motor.velocity;
  const double reach = command.motor.max_torque / stiffness;
  state.spring_angle = std::clamp(state.spring_angle, joint.angle - reach, joint.angle + reach) + velocity * dt;
  const double compliance = 1.0 / (stiffness * dt + damping);
  command.motor.velocity = compliance * (stiffness * (state.spring_angle - joint.angle) + damping * velocity);
  command.compliance = compliance;
}

// The gear side moves at the commanded velocity inside the gap; only when it pushes on a wall does the motor act
// on the output, and the friction with it (gearbox friction, on the gear's side). A tooth pushes and never pulls:
// against the upper wall (gear = output + half the width) it can only turn the output forwards, against the lower
// one only backwards. While it pushes, the gear turns with the output — also when it slows or turns back and the
// load keeps the output on it (lowering a weight). Contact ends when what the tooth passed on in the last step,
// the motor's torque plus the friction's, had the wrong sign for its wall: the load changed sign, or the gear
// braked or turned back and the output ran on. Then the output crosses the gap freely until gear and output meet
// again, which the step foresees from their rates (the gear's commanded velocity, the output's present rate).
void ApplyBacklash(const MotorEffects& effects, MotorEffectState& state, const JointReading& joint, double dt,
                   double gear_velocity, EffectCommand& command) {
  const double half = 0.5 * DegreesToRadians(std::max(effects.backlash_width, 0.0));
  if (half == 0.0) {  // no gap: nothing to cross, the stiff gear of the base model
    state.wall = 0;
    state.engaged = true;
    state.gear_angle = joint.angle;
    return;
  }
  int wall = 0;
  double gear = 0.0;  // where the gear stands at the start of this step
  if (state.wall != 0) {
    // The friction opposed the joint's rate; at rest it may have taken either sign, so it may have been the push.
    const double friction = command.motor.friction_torque;  // this step's: the last step's, up to the speed change
    const double brake =
        std::abs(joint.rate) > kRestRate ? -std::copysign(friction, joint.rate) : state.wall * friction;
    if (state.wall * (joint.motor_torque + brake) >= 0.0) wall = state.wall;  // it pushed: it goes on pushing
    gear = joint.angle + state.wall * half;
  } else {
    gear = std::clamp(state.gear_angle, joint.angle - half, joint.angle + half);  // the output may have swung onto it
    const double relative = gear - joint.angle + (gear_velocity - joint.rate) * dt;  // at the end of the step
    wall = relative >= half - kWallTolerance ? 1 : relative <= -half + kWallTolerance ? -1 : 0;
  }
  state.wall = wall;
  state.engaged = wall != 0;
  state.gear_angle = wall != 0 ? joint.angle + wall * half : gear + gear_velocity * dt;
  if (!state.engaged) {
    command.motor.max_torque = 0.0;
    command.motor.friction_torque = 0.0;
  }
}

}  // namespace

bool MotorEffects::any() const {
  return transport_delay || dead_band || back_emf || stribeck || load_friction || gravity_load_friction ||
         gear_efficiency || back_drive || backlash || elasticity || rotor_inertia || lugre;
}

double GearEfficiencyFriction(const MotorEffects& effects, double torque, double stall) {
  const double mu = std::clamp(effects.efficiency_coefficient, 0.0, 1.0);
  const double q = std::clamp(effects.efficiency_curvature, 0.0, 1.0) * (1.0 - mu) / (2.0 * std::max(stall, 1e-9));
  return mu * std::abs(torque) + q * torque * torque;
}

double LuGreFriction(const MotorEffects& effects, double rate, double dt, MotorEffectState& state) {
  const double sigma0 = std::max(effects.bristle_stiffness, 1e-9);
  const double coulomb = std::max(effects.coulomb_torque, 0.0);
  const double stiction = std::max(effects.stiction_torque, coulomb);
  if (std::abs(rate) <= kRestRate) {  // the brake holds: the bristles take whatever load up to Fs
    state.resting = true;
    return stiction;
  }
  if (state.resting) state.bristle = std::copysign(stiction / sigma0, rate);  // broken away: fully loaded
  state.resting = false;
  const double ratio = rate / std::max(effects.lugre_velocity, 1e-9);
  const double g = std::max(coulomb + (stiction - coulomb) * std::exp(-ratio * ratio), 1e-12);  // N·m
  // dz/dt = ω − σ0·|ω|·z/g is linear in z for a constant ω: z relaxes to its sliding value ω/|ω|·g/σ0 at the rate
  // σ0·|ω|/g. The exact step stays stable however stiff the bristles are.
  const double before = state.bristle;
  const double sliding = std::copysign(g / sigma0, rate);
  state.bristle = sliding + (before - sliding) * std::exp(-sigma0 * std::abs(rate) * dt / g);
  const double rate_of_bristle = (state.bristle - before) / dt;
  return std::abs(sigma0 * state.bristle + std::max(effects.bristle_damping, 0.0) * rate_of_bristle);
}

void ResetEffects(MotorEffectState& state, double angle_rad) {
  state = MotorEffectState{};
  state.gear_angle = angle_rad;
  state.spring_angle = angle_rad;
}

void CheckEffectsFitServo(const ServoParameters& servo, const MotorEffects& effects) {
  if (servo.enabled && effects.elasticity) {
    throw InputError("/Effects/Elasticity/Enabled: the gear-train spring cannot be combined with /Servo/Enabled (the "
                     "DC motor takes the motor row's compliance); turn one of them off");
  }
}

EffectCommand UpdateWithEffects(const DynamixelParameters& parameters, const ServoParameters& servo,
                                const MotorEffects& effects, DynamixelState& state, MotorEffectState& effect_state, const JointReading& joint,
                                double desired_angle_deg, double desired_torque_raw, double dt, RandomStream* noise) {
  ORCS_DEMAND(dt > 0.0);
  // Stages that change what the controller sees.
  if (effects.transport_delay) {
    PushCommand(effect_state, desired_angle_deg, desired_torque_raw);
    const double steps_back = std::max(effects.delay, 0.0) / dt;
    desired_angle_deg = Delayed(effect_state.angle_history, effect_state, steps_back);
    desired_torque_raw = Delayed(effect_state.torque_history, effect_state, steps_back);
  }
  if (effects.dead_band) desired_angle_deg = DeadBandTarget(joint.angle, desired_angle_deg, effects.margin);

  EffectCommand command;
  // The torque the gear train carries, for the friction that grows with it. The original's motor is a constraint
  // whose torque is known only after the step, so the last step's serves; the DC motor's is known now, from this
  // step's duty. At 5 ms steps the last step's lags enough to add a discretisation error of its own.
  double load_torque = joint.motor_torque;
  if (servo.enabled) {
    const ServoCommand base =
        ServoUpdate(servo, state, joint.angle, joint.rate, desired_angle_deg, desired_torque_raw, dt);
    command = {base.motor, base.compliance};
    load_torque = base.torque;
  } else {
    command = {Update(parameters, state, joint.angle, desired_angle_deg, desired_torque_raw, dt, noise), 0.0};
  }

  // Stages that change what the motor can do.
  const double speed = std::abs(joint.rate);
  if (effects.back_emf) {
    command.motor.max_torque *= std::max(0.0, 1.0 - speed / std::max(effects.no_load_speed, 1e-9));
  }
  if (effects.stribeck) {
    const double ratio = speed / std::max(effects.stribeck_velocity, 1e-9);
    command.motor.friction_torque += std::max(effects.breakaway_torque, 0.0) * std::exp(-ratio * ratio);
  }
  if (effects.load_friction) {
    command.motor.friction_torque += std::max(effects.load_coefficient, 0.0) * std::abs(load_torque);
  }
  if (effects.gravity_load_friction) {
    command.motor.friction_torque +=
        std::max(effects.gravity_load_coefficient, 0.0) * std::abs(joint.gravity_torque - load_torque);
  }
  if (effects.gear_efficiency) {
    const double stall = servo.enabled ? StallTorque(servo) : parameters.fmax_factor;
    command.motor.friction_torque += GearEfficiencyFriction(effects, load_torque, stall);
  }
  if (effects.back_drive) {
    if (speed > kRestRate) effect_state.back_driven = joint.rate * load_torque < 0.0;
    if (effect_state.back_driven) {
      command.motor.friction_torque += std::max(effects.back_drive_coefficient, 0.0) * std::abs(load_torque);
    }
  }
  if (effects.lugre) command.motor.friction_torque += LuGreFriction(effects, joint.rate, dt, effect_state);
  const double gear_velocity = command.motor.velocity;
  if (effects.elasticity) ApplyElasticity(effects, effect_state, joint, dt, command);
  if (effects.backlash) ApplyBacklash(effects, effect_state, joint, dt, gear_velocity, command);
  return command;
}

}  // namespace orcs::aseries
