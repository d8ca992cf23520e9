// The physical signature of every motor effect (model/aseries/motor_effects.h, docs/gap.md): what each one does
// to a joint that the base Dynamixel model cannot do, checked where it shows — in UpdateWithEffects itself for
// the static laws (torque limit, friction), and on the driven pendulum rig (scenarios/environments/pendulum.xml:
// a 0.5 kg, 0.3 m pole on one AX-12+) for everything dynamic. Noise is off; joint angles and rates are read
// from the physics, not from the noisy JointAngle value. Thresholds come from the physics of the rig (inertia
// and gravity torque from its own description) with the margin each comment gives; the figures in the
// comments are what the tests measured with dt = 0.01 s.
#include "model/aseries/motor_effects.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "model/aseries/value_range.h"
#include "tests/model/aseries/pendulum_rig.h"
#include "model/control/keyframe_player.h"
#include "model/control/keyframe_record.h"
#include "model/core/random_stream.h"
#include "model/core/text.h"
#include "model/physics/ode/ode_world.h"
#include "model/scene/environment_reader.h"
#include "model/scene/simulation.h"

namespace orcs::aseries {
namespace {

constexpr double kDt = 0.01;  // s, the simulation's default step
constexpr double kPi = std::numbers::pi;
constexpr double kDegrees = 180.0 / kPi;

// An angle in radians as the repository's text, in degrees (/Effects/DeadBand/Margin, /Effects/Backlash/Width).
std::string DegreesText(double radians) { return text::FormatDouble(radians * kDegrees); }
constexpr double kFullTorque = 1.04803939;  // N·m: DesiredTorque 1 × FMaxFactor
constexpr double kDefaultTorque = kFullTorque * kDefaultDesiredTorqueRaw;  // 0.615 N·m

Values Effect(const std::string& name, const Values& parameters) {
  Values values{{"/Effects/" + name + "/Enabled", "true"}};
  values.insert(values.end(), parameters.begin(), parameters.end());
  return values;
}

// The joint angle (degrees) after each of `steps` steps from rest at 0 on `engine`, commanded to `degrees` at full
// torque after `settle` steps.
std::vector<double> StepResponse(const std::string& engine, const Values& values, double degrees, int steps,
                                 int settle = 50) {
  PendulumRig rig(values, engine);
  rig.Command(0.0);
  rig.Run(settle);
  rig.Command(degrees);
  std::vector<double> angles;
  for (int i = 0; i < steps && rig.Step(); ++i) angles.push_back(rig.Degrees());
  return angles;
}

// Crossings of angle 0 upwards, linearly interpolated between steps, s.
std::vector<double> UpwardZeroCrossings(PendulumRig& rig, int steps) {
  std::vector<double> crossings;
  double previous = rig.Degrees();
  for (int i = 0; i < steps && rig.Step(); ++i) {
    const double now = rig.Degrees();
    if (previous < 0.0 && now >= 0.0) crossings.push_back((i + previous / (previous - now)) * kDt);
    previous = now;
  }
  return crossings;
}

// The tests on the rig run on both engines (issue 20: the pendulum rig's step responses hold on MuJoCo too).
class MotorEffectsRigTest : public ::testing::TestWithParam<std::string> {};
INSTANTIATE_TEST_SUITE_P(Engines, MotorEffectsRigTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const ::testing::TestParamInfo<std::string>& engine) { return engine.param; });

double MeanPeriod(const std::vector<double>& crossings) {
  EXPECT_GE(crossings.size(), 3u);
  if (crossings.size() < 2) return 0.0;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

// ---------------------------------------------------------------------------------------------------------------
// Every effect off: the base model, bit for bit.

TEST(MotorEffectsTest, EveryEffectOffReturnsTheBaseCommandBitForBit) {
  // UpdateWithEffects with MotorEffects{} must be Update: the same velocity, torque limit and friction bits, no
  // compliance, the same controller memory and the same noise draws, over a sequence that exercises the P, I
  // and D parts, the velocity clip, the static/dynamic friction switch and the desired-torque clamp.
  DynamixelParameters parameters;
  parameters.ki = 0.3;
  parameters.kd = 0.002;
  parameters.motor_noise = 0.05;
  const MotorEffects off;
  ASSERT_FALSE(off.any());
  DynamixelState base_state{};
  DynamixelState effect_state{};
  MotorEffectState memory{};
  Reset(base_state, 0.1);
  Reset(effect_state, 0.1);
  ResetEffects(memory, 0.1);
  RandomStream base_noise(7, "test/motor-noise");
  RandomStream effect_noise(7, "test/motor-noise");
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (int i = 0; i < 200; ++i) {
    const double angle = 0.1 + 0.8 * std::sin(0.07 * i);
    const JointReading joint{angle, 3.0 * std::cos(0.11 * i), 0.7 * std::sin(0.05 * i)};
    const double desired = 170.0 * std::sin(0.013 * i);                 // beyond ±150° at times
    const double torque = -0.2 + 1.5 * (0.5 + 0.5 * std::sin(0.03 * i));  // −0.2 … 1.3: both clamps
    const DynamixelCommand expected = Update(parameters, base_state, angle, desired, torque, kDt, &base_noise);
    const EffectCommand actual =
        UpdateWithEffects(parameters, ServoParameters{}, off, effect_state, memory, joint, desired, torque, kDt, &effect_noise);
    ASSERT_EQ(bits(actual.motor.velocity), bits(expected.velocity)) << "step " << i;
    ASSERT_EQ(bits(actual.motor.max_torque), bits(expected.max_torque)) << "step " << i;
    ASSERT_EQ(bits(actual.motor.friction_torque), bits(expected.friction_torque)) << "step " << i;
    ASSERT_EQ(actual.compliance, 0.0);
    ASSERT_EQ(bits(effect_state.previous_error), bits(base_state.previous_error));
  }
}

TEST_P(MotorEffectsRigTest, EffectsAtZeroStrengthLeaveAPendulumRunAsItWas) {
  // The original team's motion (scenarios/motions/pendulum_steps.csv, 17 s: steps to ±90° at full and at the
  // default torque) with an effect switched on at zero strength must match the run with every effect off: the
  // switch alone changes nothing physical. Measured: exactly equal for all three.
  const auto run = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    aseries::ASeriesAgent& agent = rig.simulation().agent(0);
    control::KeyframePlayer player(
        control::ReadKeyframeRecord(SourcePath("scenarios/motions/pendulum_steps.csv"), agent.motor_count()),
        "Pendulum", agent.motor_names(), rig.simulation().repository());
    std::vector<double> angles;
    while (rig.simulation().time() < 17.0 - 1e-9) {
      player.Apply(rig.simulation().time());
      if (!rig.Step()) break;
      angles.push_back(rig.Degrees());
    }
    return angles;
  };
  const std::vector<double> off = run({});
  ASSERT_EQ(off.size(), 1700u);
  for (const Values& zero : {Effect("TransportDelay", {{"/Effects/TransportDelay/Delay", "0"}}),
                             Effect("DeadBand", {{"/Effects/DeadBand/Margin", "0"}}),
                             Effect("Backlash", {{"/Effects/Backlash/Width", "0"}})}) {
    const std::vector<double> on = run(zero);
    ASSERT_EQ(on.size(), off.size()) << zero[0].first;
    double largest = 0.0;
    for (size_t i = 0; i < off.size(); ++i) largest = std::max(largest, std::abs(on[i] - off[i]));
    EXPECT_LT(largest, 1e-6) << zero[0].first;  // degrees
  }
}

// ---------------------------------------------------------------------------------------------------------------
// TransportDelay

TEST_P(MotorEffectsRigTest, TransportDelayShiftsTheStepResponseByTheDelay) {
  // A 2° step (small enough that the controller's velocity is not clipped) with a 0.05 s delay: for 5 steps the
  // pole does not move at all, then it follows the undelayed response exactly, 5 steps late (the motor sees the
  // same commands in the same state; measured bit-identical).
  const std::vector<double> base = StepResponse(GetParam(), {}, 2.0, 40);
  const std::vector<double> late =
      StepResponse(GetParam(), Effect("TransportDelay", {{"/Effects/TransportDelay/Delay", "0.05"}}), 2.0, 40);
  ASSERT_EQ(late.size(), 40u);
  EXPECT_GT(base[0], 0.1);  // without delay the pole moves in the first step (0.40°)
  for (int i = 0; i < 5; ++i) EXPECT_LT(std::abs(late[i]), 1e-9) << "step " << i;
  for (int i = 5; i < 40; ++i) EXPECT_NEAR(late[i], base[i - 5], 1e-12) << "step " << i;
}

TEST_P(MotorEffectsRigTest, TransportDelayInterpolatesFractionalDelays) {
  // 0.025 s is 2.5 steps: the motor sees the average of the commands 2 and 3 steps back (half the step first),
  // so the response lies between those with 0.02 s and 0.03 s delay, strictly while the pole is moving.
  const auto delayed = [](const char* delay) {
    return StepResponse(GetParam(), Effect("TransportDelay", {{"/Effects/TransportDelay/Delay", delay}}), 2.0, 30);
  };
  const std::vector<double> early = delayed("0.02");
  const std::vector<double> between = delayed("0.025");
  const std::vector<double> late = delayed("0.03");
  ASSERT_EQ(between.size(), 30u);
  for (int i = 0; i < 2; ++i) EXPECT_LT(std::abs(between[i]), 1e-9) << "step " << i;
  EXPECT_NEAR(between[2], 0.5 * early[2], 0.01 * early[2]);  // half the command: half the first step's motion
  for (int i = 2; i < 30; ++i) {
    EXPECT_GT(between[i], late[i]) << "step " << i;
    EXPECT_LT(between[i], early[i]) << "step " << i;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// DeadBand

TEST_P(MotorEffectsRigTest, DeadBandIgnoresCommandsWithinTheMargin) {
  // Margin 0.03 rad (1.72°): a command of 1° does not move the pole at all; without the effect it goes there.
  const Values dead_band = Effect("DeadBand", {{"/Effects/DeadBand/Margin", DegreesText(0.03)}});
  for (const double target : {1.0, -1.0}) {
    const std::vector<double> with = StepResponse(GetParam(), dead_band, target, 200);
    const std::vector<double> without = StepResponse(GetParam(), {}, target, 200);
    double largest = 0.0;
    for (double angle : with) largest = std::max(largest, std::abs(angle));
    EXPECT_LT(largest, 1e-9) << target;
    EXPECT_NEAR(without.back(), target, 1e-3);
  }
}

TEST_P(MotorEffectsRigTest, DeadBandStopsShortOfTheTargetByTheMargin) {
  // Beyond the margin the controller sees the error less the margin, so the pole stops the margin short of the
  // target, on the side it came from, with or without a gravity load (5°: nearly none; 30°: 0.37 N·m).
  // Measured: an error of 0.030000 rad in all three cases; without the effect 0.
  constexpr double kMargin = 0.03;
  const Values dead_band = Effect("DeadBand", {{"/Effects/DeadBand/Margin", DegreesText(0.03)}});
  for (const double target : {5.0, -5.0, 30.0}) {
    const double error = (target - StepResponse(GetParam(), dead_band, target, 200).back()) / kDegrees;
    EXPECT_NEAR(error, std::copysign(kMargin, target), 1e-4) << target;
    EXPECT_NEAR((target - StepResponse(GetParam(), {}, target, 200).back()) / kDegrees, 0.0, 1e-5) << target;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// BackEmf

TEST(MotorEffectsTest, BackEmfTorqueLimitFallsLinearlyWithSpeedToZeroAtTheNoLoadSpeed) {
  DynamixelParameters parameters;
  MotorEffects effects;
  effects.back_emf = true;
  effects.no_load_speed = 5.0;
  const double full = TorqueLimit(parameters, 1.0);
  for (const double rate : {0.0, 1.0, -1.0, 2.5, -4.0, 4.999, 5.0, 7.0, -20.0}) {
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(state, 0.2);
    ResetEffects(memory, 0.2);
    const EffectCommand command =
        UpdateWithEffects(parameters, ServoParameters{}, effects, state, memory, {0.2, rate, 0.0}, 30.0, 1.0, kDt, nullptr);
    EXPECT_NEAR(command.motor.max_torque, full * std::max(0.0, 1.0 - std::abs(rate) / 5.0), 1e-12) << rate;
    EXPECT_GE(command.motor.max_torque, 0.0) << rate;
  }
}

TEST_P(MotorEffectsRigTest, BackEmfSlowsAFastLiftAndCapsItsSpeedBelowTheNoLoadSpeed) {
  // Lift from hanging to 90° at full torque. Without the effect the lift runs at the 3.5 rad/s velocity clip
  // and passes 80° after 0.46 s. With a no-load speed of 5 rad/s the torque left at speed is what gravity and
  // friction take, so the lift tops out at 2.45 rad/s and passes 80° only after 0.95 s; with 2 rad/s it never
  // exceeds 1.45 rad/s. The margins below are half the measured differences.
  const auto lift = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(90.0);
    double fastest = 0.0;
    double passed_80 = -1.0;
    for (int i = 0; i < 300 && rig.Step(); ++i) {
      fastest = std::max(fastest, rig.Rate());
      if (passed_80 < 0.0 && rig.Degrees() >= 80.0) passed_80 = (i + 1) * kDt;
    }
    EXPECT_NEAR(rig.Degrees(), 90.0, 0.1);  // at rest the whole torque is there: it still gets there
    return std::pair{fastest, passed_80};
  };
  const auto [fastest_off, time_off] = lift({});
  const auto [fastest_5, time_5] = lift(Effect("BackEmf", {{"/Effects/BackEmf/NoLoadSpeed", "5"}}));
  const auto [fastest_2, time_2] = lift(Effect("BackEmf", {{"/Effects/BackEmf/NoLoadSpeed", "2"}}));
  EXPECT_NEAR(fastest_off, 3.5, 1e-3);
  EXPECT_LT(fastest_5, 3.0);
  EXPECT_LT(fastest_2, 1.75);
  EXPECT_LT(fastest_2, 2.0);  // the no-load speed itself
  EXPECT_LT(time_off, 0.5);
  EXPECT_GT(time_5, time_off + 0.25);
  EXPECT_GT(time_2, time_5 + 0.4);
}

// ---------------------------------------------------------------------------------------------------------------
// Stribeck

TEST(MotorEffectsTest, StribeckFrictionIsTheBreakawayTorqueAtRestAndVanishesWithSpeed) {
  // Added friction B·exp(−(ω/vs)²): B at rest, B/e at vs, below 2 % of B at 2·vs (exp(−4) = 1.8 %), in either
  // direction, on top of the base model's friction.
  DynamixelParameters parameters;
  MotorEffects effects;
  effects.stribeck = true;
  effects.breakaway_torque = 0.2;
  effects.stribeck_velocity = 0.1;
  const auto added = [&](double rate) {
    DynamixelState base{};
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(base, 0.0);
    Reset(state, 0.0);
    ResetEffects(memory, 0.0);
    // The base friction uses the finite-difference speed: give it the same angle step as the rate.
    const double angle = rate * kDt;
    const double base_friction = Update(parameters, base, angle, 0.0, 1.0, kDt, nullptr).friction_torque;
    return UpdateWithEffects(parameters, ServoParameters{}, effects, state, memory, {angle, rate, 0.0}, 0.0, 1.0, kDt, nullptr)
               .motor.friction_torque -
           base_friction;
  };
  EXPECT_NEAR(added(0.0), 0.2, 1e-12);
  EXPECT_NEAR(added(0.1), 0.2 / std::exp(1.0), 1e-9);
  EXPECT_NEAR(added(-0.1), 0.2 / std::exp(1.0), 1e-9);
  EXPECT_LT(added(0.2), 0.02 * 0.2);
  EXPECT_LT(added(-0.2), 0.02 * 0.2);
  EXPECT_GT(added(0.2), 0.0);
  EXPECT_LT(added(1.0), 1e-12);
}

TEST_P(MotorEffectsRigTest, StribeckStictionHoldsAReleasedPoleOnlyBelowTheBreakawayTorque) {
  // The pole released at rest at 10° with the motor limp (DesiredTorque 0) and no viscous joint friction:
  // gravity pulls with m·g·d·sin 10° = 0.128 N·m. A breakaway torque of 0.15 N·m holds it where it is (it moves
  // less than 1e-3°). 0.10 N·m does not, and once the pole moves the friction fades: it swings through the
  // bottom to −9.9° (without the effect −10.0°). A Coulomb friction of 0.10 N·m that did not fade would stop it
  // near −5.6° (10° less twice asin(0.10/0.736)); the bound −9° lies between.
  const auto release = [](const Values& values) {
    Values limp = values;
    limp.push_back({"/AngularMotor/DynamicFriction", "0"});
    PendulumRig rig(limp, GetParam());
    rig.Pose(10.0);
    rig.Command(10.0, 0.0);
    double lowest = rig.Degrees();
    for (int i = 0; i < 100 && rig.Step(); ++i) lowest = std::min(lowest, rig.Degrees());
    return lowest;
  };
  PendulumRig rig({}, GetParam());
  ASSERT_NEAR(rig.GravityTorque() * std::sin(10.0 / kDegrees), 0.128, 1e-3);
  EXPECT_GT(release(Effect("Stribeck", {{"/Effects/Stribeck/BreakawayTorque", "0.15"}})), 10.0 - 1e-3);
  EXPECT_LT(release(Effect("Stribeck", {{"/Effects/Stribeck/BreakawayTorque", "0.10"}})), -9.0);
  EXPECT_LT(release({}), -9.0);
}

// ---------------------------------------------------------------------------------------------------------------
// Torque control (/AngularMotor/TorqueControl, docs/model.md "Differences", item 8)

TEST_P(MotorEffectsRigTest, TorqueControlHoldsThePoleWhereGravityBalancesTheCommandedTorque) {
  // Under torque control the motor pushes with the commanded torque τ whatever the angle: the pole settles where
  // gravity's m·g·d·sin θ equals τ, on the side τ points to. Friction (fs 0.001 N·m at rest) shifts that by less
  // than 0.1°. Under position control the same command is a torque limit and the pole stays at its goal, 0°.
  PendulumRig probe({}, GetParam());
  const double gravity = probe.GravityTorque();  // m·g·d, N·m
  const auto settle = [&](bool torque_control, double torque_nm) {
    PendulumRig rig({{"/AngularMotor/TorqueControl", torque_control ? "true" : "false"}}, GetParam());
    rig.Command(0.0, torque_nm / kFullTorque);
    rig.Run(400);
    return rig.Degrees();
  };
  for (const double torque : {0.2, 0.45, -0.3}) {
    const double expected = std::asin(torque / gravity) * kDegrees;
    EXPECT_NEAR(settle(true, torque), expected, 0.5) << torque << " N·m";
  }
  EXPECT_NEAR(settle(false, 0.45), 0.0, 0.5) << "position control holds its goal";
}

// ---------------------------------------------------------------------------------------------------------------
// The original's friction form (/AngularMotor/OriginalFriction, docs/model.md "Differences", item 6)

TEST_P(MotorEffectsRigTest, OriginalFrictionBrakesByTheCommandWhereTheSuccessorsBrakesByTheMotion) {
  // The pole released at rest at 30° with the motor limp (DesiredTorque 0): gravity pulls with m·g·d·sin 30° =
  // 0.368 N·m. The successor's brake follows the measured speed (fs at rest, then αd·|ω|): the pole falls either
  // way and its swing is damped, so it stops short of −30°. The original's brake follows the commanded velocity:
  // commanded up (+150°, v = +3.5 rad/s, f = αd·3.5 = 0.56 N·m > 0.368) it holds the pole where it was released;
  // commanded down (−150°, v = −3.5, f = −0.56: no brake) the pole swings freely to the mirror angle.
  const auto release = [](bool original, double desired) {
    PendulumRig rig({{"/AngularMotor/OriginalFriction", original ? "true" : "false"}}, GetParam());
    rig.Pose(30.0);
    rig.Command(desired, 0.0);
    double lowest = rig.Degrees();
    for (int i = 0; i < 100 && rig.Step(); ++i) lowest = std::min(lowest, rig.Degrees());
    return lowest;
  };
  PendulumRig rig({}, GetParam());
  ASSERT_NEAR(rig.GravityTorque() * 0.5, 0.368, 1e-3);
  EXPECT_GT(release(true, 150.0), 30.0 - 0.1) << "the original's brake holds the pole";
  EXPECT_LT(release(true, -150.0), -29.5) << "the original's form brakes nothing: a free swing";
  const double successor_up = release(false, 150.0);
  const double successor_down = release(false, -150.0);
  EXPECT_EQ(successor_up, successor_down) << "the successor's brake ignores the command";
  EXPECT_LT(successor_up, 0.0) << "the successor's brake does not hold the pole";
  EXPECT_GT(successor_up, -29.0) << "the successor's brake damps the swing";
}

// ---------------------------------------------------------------------------------------------------------------
// LuGre

TEST(MotorEffectsTest, LuGreHoldsAtRestFollowsTheStribeckCurveAndLagsBehindASpeedChange) {
  MotorEffects effects;
  effects.lugre = true;
  effects.bristle_stiffness = 50.0;  // σ0, N·m/rad
  effects.bristle_damping = 0.0;
  effects.coulomb_torque = 0.05;     // Fc
  effects.stiction_torque = 0.2;     // Fs
  effects.lugre_velocity = 0.1;      // vs
  const auto g = [](double rate) { return 0.05 + 0.15 * std::exp(-(rate / 0.1) * (rate / 0.1)); };
  MotorEffectState state;
  EXPECT_EQ(LuGreFriction(effects, 0.0, kDt, state), 0.2) << "at rest: the stiction";
  // Sliding steadily, the friction settles on g(ω) = Fc + (Fs − Fc)·exp(−(ω/vs)²), from Fs near rest to Fc.
  for (const double rate : {0.02, 0.1, 1.0, -0.3}) {
    MotorEffectState sliding;
    double friction = 0.0;
    for (int i = 0; i < 2000; ++i) friction = LuGreFriction(effects, rate, kDt, sliding);
    EXPECT_NEAR(friction, g(rate), 1e-9) << rate << " rad/s";
    EXPECT_NEAR(sliding.bristle, std::copysign(g(rate) / 50.0, rate), 1e-12) << "the sliding deflection";
  }
  // Breaking away at 1 rad/s with soft bristles (σ0 = 2 N·m/rad: they relax at σ0·ω/g = 40 per second), the
  // bristles start loaded to Fs and the friction falls towards Fc over several steps, not at once as a static
  // Stribeck curve would.
  effects.bristle_stiffness = 2.0;
  MotorEffectState broken;
  std::vector<double> after;
  for (int i = 0; i < 40; ++i) after.push_back(LuGreFriction(effects, 1.0, kDt, broken));
  EXPECT_GT(after[0], 0.12) << "just broken away: still near Fs";
  EXPECT_NEAR(after[39], g(1.0), 0.02) << "settled on Fc";
  for (std::size_t i = 1; i < after.size(); ++i) EXPECT_LE(after[i], after[i - 1] + 1e-12) << "falls steadily";
  // However stiff the bristles, the exact step never overshoots the sliding deflection.
  effects.bristle_stiffness = 1e7;
  MotorEffectState stiff;
  LuGreFriction(effects, 1.0, kDt, stiff);
  EXPECT_LE(LuGreFriction(effects, 1.0, kDt, stiff), g(1.0) + 1e-9);
}

TEST_P(MotorEffectsRigTest, LuGreHoldsAReleasedPoleOnlyBelowTheStictionTorque) {
  // The pole released at 10° with the motor limp and no viscous joint friction: gravity pulls with 0.128 N·m. A
  // stiction torque of 0.15 N·m holds it where it is; 0.10 N·m does not, and once it moves the friction lags down
  // to the Coulomb level: it swings through the bottom well past where a friction that stayed at 0.10 N·m
  // would stop it (−5.6°, as in the Stribeck test above).
  const auto release = [](double stiction) {
    PendulumRig rig({{"/AngularMotor/DynamicFriction", "0"},
                     {"/Effects/LuGre/Enabled", "true"},
                     {"/Effects/LuGre/BristleStiffness", "50"},
                     {"/Effects/LuGre/CoulombTorque", "0.01"},
                     {"/Effects/LuGre/StictionTorque", text::FormatDouble(stiction)}},
                    GetParam());
    rig.Pose(10.0);
    rig.Command(10.0, 0.0);
    double lowest = rig.Degrees();
    for (int i = 0; i < 150 && rig.Step(); ++i) lowest = std::min(lowest, rig.Degrees());
    return lowest;
  };
  PendulumRig rig({}, GetParam());
  ASSERT_NEAR(rig.GravityTorque() * std::sin(10.0 / kDegrees), 0.128, 1e-3);
  EXPECT_GT(release(0.15), 10.0 - 1e-3) << "held";
  EXPECT_LT(release(0.10), -7.0) << "not held: it swings through the bottom";
}

// ---------------------------------------------------------------------------------------------------------------
// LoadFriction

TEST(MotorEffectsTest, LoadFrictionGrowsInProportionToTheMotorTorque) {
  DynamixelParameters parameters;
  MotorEffects effects;
  effects.load_friction = true;
  effects.load_coefficient = 0.3;
  for (const double torque : {0.0, 0.3, -0.6, 1.0}) {
    DynamixelState base{};
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(base, 0.5);
    Reset(state, 0.5);
    ResetEffects(memory, 0.5);
    const double base_friction = Update(parameters, base, 0.5, 40.0, 1.0, kDt, nullptr).friction_torque;
    const double friction =
        UpdateWithEffects(parameters, ServoParameters{}, effects, state, memory, {0.5, 0.0, torque}, 40.0, 1.0, kDt, nullptr)
            .motor.friction_torque;
    EXPECT_NEAR(friction - base_friction, 0.3 * std::abs(torque), 1e-12) << torque;
  }
}

TEST_P(MotorEffectsRigTest, LoadFrictionMakesATorqueLimitedLiftStallLower) {
  // At the default torque τ = 0.615 N·m the motor cannot hold the pole horizontal (m·g·d = 0.736 N·m): lifting
  // towards 90° it stalls where gravity takes what friction leaves, sin θ = (τ − c·τ − fs)/(m·g·d), with fs the
  // base model's 0.001 N·m: 56.6° without load friction, 35.7° with c = 0.3 (measured 56.57° and 36.04°: the
  // pole coasts a little into the friction band before it stops).
  const auto stall = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(90.0, kDefaultDesiredTorqueRaw);
    rig.Run(300);
    EXPECT_LT(std::abs(rig.Rate()), 1e-3);
    return rig.Degrees();
  };
  const double gravity = PendulumRig({}, GetParam()).GravityTorque();
  const double off = std::asin((kDefaultTorque - 0.001) / gravity) * kDegrees;
  const double on = std::asin((0.7 * kDefaultTorque - 0.001) / gravity) * kDegrees;
  EXPECT_NEAR(stall({}), off, 0.5);
  EXPECT_NEAR(stall(Effect("LoadFriction", {{"/Effects/LoadFriction/Coefficient", "0.3"}})), on, 1.0);
}

TEST_P(MotorEffectsRigTest, LoadFrictionHoldsAPoleThatTheWeakenedMotorAloneWouldLetSag) {
  // Friction opposes motion either way, so a loaded gearbox also holds. The pole is held at 60° at full torque
  // (gravity 0.637 N·m), then the torque drops to 0.615 N·m. Without load friction it sags to where gravity
  // equals the motor (56.85°); with c = 0.3 the friction c·0.615 = 0.18 N·m makes up the difference and the
  // pole stays (measured: it moves less than 0.01°). Together with the lower stall above: a band of rest
  // angles, the hysteresis of a load-dependent friction.
  const auto sag = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(60.0, 1.0);
    rig.Run(200);
    EXPECT_NEAR(rig.Degrees(), 60.0, 0.01);
    rig.Command(60.0, kDefaultDesiredTorqueRaw);
    rig.Run(300);
    return rig.Degrees();
  };
  EXPECT_LT(sag({}), 57.5);
  EXPECT_GT(sag(Effect("LoadFriction", {{"/Effects/LoadFriction/Coefficient", "0.3"}})), 59.9);
}

// ---------------------------------------------------------------------------------------------------------------
// Backlash

TEST(MotorEffectsTest, BacklashOpenGapTakesTheMotorOffTheOutputUntilTheGearMeetsAWall) {
  // Right after a reset the gear stands in the middle of the gap. Commanded at 1 rad/s (pure P control, Kp = 1)
  // it needs half the width (0.05 rad) = 5 steps to reach the wall: until then the motor applies no torque and
  // no friction, from then on its full command.
  DynamixelParameters parameters;
  parameters.kp = 1.0;
  MotorEffects effects;
  effects.backlash = true;
  effects.backlash_width = 0.1 * kDegrees;
  DynamixelState state{};
  MotorEffectState memory{};
  Reset(state, 0.0);
  ResetEffects(memory, 0.0);
  const double desired = 1.0 * kDegrees;  // an error of 1 rad: v = 1 rad/s
  for (int i = 0; i < 8; ++i) {
    const EffectCommand command =
        UpdateWithEffects(parameters, ServoParameters{}, effects, state, memory, {0.0, 0.0, 0.0}, desired, 1.0, kDt, nullptr);
    EXPECT_NEAR(command.motor.velocity, 1.0, 1e-12);
    if (i < 4) {  // the gear at 0.01 … 0.04 rad: inside the gap
      EXPECT_EQ(command.motor.max_torque, 0.0) << "step " << i;
      EXPECT_EQ(command.motor.friction_torque, 0.0) << "step " << i;
    } else {  // at the wall (0.05 rad, within the rounding of five steps of 0.01 rad): it pushes
      EXPECT_EQ(command.motor.max_torque, kFullTorque) << "step " << i;
      EXPECT_GT(command.motor.friction_torque, 0.0) << "step " << i;
    }
  }
}

TEST(MotorEffectsTest, BacklashToothPushesButNeverPulls) {
  // The gear pushing on the upper wall: as long as what it passed on in the last step (motor torque plus the
  // friction, which opposes the rate) was positive it stays engaged; had it to pull the output back, the output
  // runs ahead and the gap opens: no torque, no friction.
  DynamixelParameters parameters;
  parameters.dynamic_friction = 0.0;
  parameters.static_friction = 0.0;
  MotorEffects effects;
  effects.backlash = true;
  effects.backlash_width = 0.1 * kDegrees;
  const auto after = [&](double last_torque) {
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(state, 0.0);
    ResetEffects(memory, 0.0);
    memory.wall = 1;  // engaged on the upper wall in the last step, moving forwards with the gear
    memory.engaged = true;
    memory.gear_angle = 0.05;
    return UpdateWithEffects(parameters, ServoParameters{}, effects, state, memory, {0.0, 0.5, last_torque}, 10.0, 1.0, kDt, nullptr);
  };
  EXPECT_EQ(after(0.3).motor.max_torque, kFullTorque);
  EXPECT_EQ(after(0.0).motor.max_torque, kFullTorque);
  EXPECT_EQ(after(-0.3).motor.max_torque, 0.0);
  EXPECT_EQ(after(-0.3).motor.friction_torque, 0.0);
}

TEST_P(MotorEffectsRigTest, BacklashHoldsASteadyLoadWithoutChattering) {
  // Held at 30° against gravity (0.37 N·m) the gear rests on one wall of a 0.06 rad gap and the pole stays put,
  // at the target (the controller's sensor is on the output). Before the fix of ApplyBacklash the gear was left
  // where the last step's clamp put it while the output moved on, so the gap opened every other step: the pole
  // chattered between 29.65° and 29.72° at ±0.12 rad/s for ever.
  PendulumRig rig(Effect("Backlash", {{"/Effects/Backlash/Width", DegreesText(0.06)}}), GetParam());
  rig.Command(30.0);
  rig.Run(100);
  double fastest = 0.0;
  for (int i = 0; i < 100 && rig.Step(); ++i) fastest = std::max(fastest, std::abs(rig.Rate()));
  EXPECT_LT(fastest, 1e-3);
  EXPECT_NEAR(rig.Degrees(), 30.0, 0.01);
}

TEST_P(MotorEffectsRigTest, BacklashLetsThePoleDropAcrossTheGapWhenTheLoadReverses) {
  // The pole held at 30° by the motor, the gear pushing on the gap's upper wall against gravity. Then the motor
  // is locked where it is (Kp = 0: it holds the gear still) and gravity is reversed, so the load pushes the pole
  // the other way. A tooth cannot pull: the pole swings across the gap with gravity's acceleration alone
  // (m·g·d·sin θ/I, within 1 %: the motor applies nothing) until it has turned by the width, where the gear's
  // other wall catches it and the motor stops it. Without backlash the locked motor holds it where it was.
  // dt = 1 ms, so that a step's travel (2e-3 rad at the wall) is small against the width: the free travel
  // measured 0.973 and 0.981 widths (the motor's wall is foreseen within a step).
  const auto reverse_load = [](const Values& values) {
    Values fine = values;
    fine.push_back({"/Simulation/TimeStepSize", "0.001"});
    PendulumRig rig(fine, GetParam());
    rig.Command(30.0);
    rig.Run(1000);
    rig.Set("/AngularMotor/PID/Proportional", "0");
    rig.Set("/Simulation/Gravitation", "-9.81");
    const double inertia = rig.Inertia();
    const double gravity = rig.GravityTorque();
    const double start = rig.Degrees() / kDegrees;
    double angle = start;
    double rate = rig.Rate();
    double free_travel = -1.0;
    for (int i = 0; i < 500 && rig.Step(); ++i) {
      const double now = rig.Degrees() / kDegrees;
      const double acceleration = (rig.Rate() - rate) / 0.001;
      const double free = gravity * std::sin(0.5 * (angle + now)) / inertia;  // reversed gravity lifts it
      // Step 0 still felt the motor (the tooth's contact is judged from the last step's torque).
      if (i > 0 && free_travel < 0.0) {
        if (std::abs(acceleration - free) > 0.05 * free) {
          free_travel = angle - start;
        } else {
          EXPECT_NEAR(acceleration, free, 0.01 * free) << "step " << i;
        }
      }
      angle = now;
      rate = rig.Rate();
    }
    return std::pair{free_travel, angle - start};
  };
  const auto [free_off, moved_off] = reverse_load({});
  EXPECT_LT(std::abs(moved_off), 1e-4);
  for (const double width : {0.06, 0.12}) {
    const auto [free_travel, moved] =
        reverse_load(Effect("Backlash", {{"/Effects/Backlash/Width", DegreesText(width)}}));
    EXPECT_NEAR(free_travel, width, 0.05 * width) << width;
    // At rest beyond it, held by the locked motor. Energy bounds the stop: the motor brakes at its full torque τ
    // over moved − free travel what gravity gave over the whole way, at most its torque at the end times moved.
    EXPECT_GT(moved, width) << width;
    const double load = PendulumRig({}, GetParam()).GravityTorque() * std::sin(30.0 / kDegrees + moved);
    // Measured 0.085 and 0.172 rad against bounds of 0.100 and 0.218.
    EXPECT_LT(moved, kFullTorque * width / (kFullTorque - load)) << width;
  }
}

TEST_P(MotorEffectsRigTest, BacklashShiftsTheMotorSideByTheWidthWhereTheLoadChangesSign) {
  // A slow ±30° sine (period 8 s) swings the pole through the bottom, where gravity's load changes sign. The
  // motor side's angle is the integral of the commanded velocity (CurrentVelocity). Without backlash it is the
  // output's angle (to the motor's 1e-5 rad/s per N·m yield). With a 0.06 rad gap the gear rests on the wall
  // that carries the load: above the bottom half a width ahead of the output, below it half a width behind,
  // going down and going up alike (the gravity side decides, not the direction: no hysteresis in the angle
  // away from the bottom). At the bottom the tooth would have to pull, the output swings free for a moment and
  // the motor side jumps by the width relative to it (measured: 0.0566 rad at each crossing). The output itself
  // — sensor and controller act on it — lags the effect-off run only for those moments: 0.46 widths at most,
  // gone 0.25 s later: the residual's blip at a load reversal.
  constexpr double kWidth = 0.06;
  struct Run {
    std::vector<double> output;  // rad
    std::vector<double> offset;  // motor side − output, rad
  };
  const auto sine = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    Run run;
    double motor_side = 0.0;
    for (int i = 0; i < 1600; ++i) {
      rig.Command(30.0 * std::sin(2.0 * kPi * i * kDt / 8.0));
      if (!rig.Step()) break;
      motor_side += rig.simulation().repository().Get("/Sim/Pendulum/Motor/CurrentVelocity").as_double() * kDt;
      run.output.push_back(rig.Degrees() / kDegrees);
      run.offset.push_back(motor_side - rig.Degrees() / kDegrees);
    }
    return run;
  };
  const Run off = sine({});
  const Run on = sine(Effect("Backlash", {{"/Effects/Backlash/Width", DegreesText(0.06)}}));
  ASSERT_EQ(off.output.size(), 1600u);
  ASSERT_EQ(on.output.size(), 1600u);
  for (double offset : off.offset) ASSERT_LT(std::abs(offset), 1e-3);
  // Steps (t = 0.01·(i + 1)) where the output passes ±20°: down at t ≈ 2.9 s and 5.1 s, up at 8.9 s and 11.1 s.
  const auto at = [&on](double seconds) { return on.offset[static_cast<size_t>(std::lround(seconds / kDt)) - 1]; };
  const double above_down = at(2.9), below_down = at(5.1), below_up = at(6.9), above_up = at(9.1);
  EXPECT_GT(above_down, 0.0);
  EXPECT_LT(below_down, 0.0);
  EXPECT_NEAR(above_down - below_down, kWidth, 0.1 * kWidth);  // the jump going down through the bottom
  EXPECT_NEAR(above_up - below_up, kWidth, 0.1 * kWidth);      // and going up through it
  EXPECT_NEAR(above_up, above_down, 0.05 * kWidth);            // the same wall going up as going down
  EXPECT_NEAR(below_up, below_down, 0.05 * kWidth);
  // The output: a blip after each bottom crossing (t = 4 s going down, 8 s going up), nothing elsewhere.
  for (const double crossing : {4.0, 8.0, 12.0}) {
    double largest = 0.0;
    for (double t = crossing - 0.5; t < crossing + 0.5; t += kDt) {
      const size_t i = static_cast<size_t>(std::lround(t / kDt));
      largest = std::max(largest, std::abs(on.output[i] - off.output[i]));
    }
    EXPECT_GT(largest, 0.3 * kWidth) << crossing;
    EXPECT_LT(largest, 0.6 * kWidth) << crossing;
    for (double t = crossing + 0.6; t < crossing + 3.4; t += kDt) {
      const size_t i = static_cast<size_t>(std::lround(t / kDt));
      ASSERT_LT(std::abs(on.output[i] - off.output[i]), 0.01 * kWidth) << "t = " << t;
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Elasticity

TEST_P(MotorEffectsRigTest, CompliantMotorRowIsAnImplicitSpringOfTheGivenStiffness) {
  // The recipe of PhysicsWorld::SetJointMotorCompliance on the rig's pole, without gravity: every step the
  // motor row gets compliance c = 1/(k·dt) and target velocity c·k·(0 − θ), i.e. a spring k to angle 0. Kicked
  // at 0.5 rad/s the pole oscillates at ω = √(k/I) (k = 5 N·m/rad, I = 0.01503 kg·m²: 18.24 rad/s) within 2 %;
  // exactly (to 0.2 %) at atan(ω·dt)/dt = 18.04 rad/s and losing amplitude by 1/√(1 + (ω·dt)²) per step, as
  // implicit Euler does: the spring is implicit — it can never gain energy, whatever k.
  PendulumRig rig({}, GetParam());
  const double inertia = rig.Inertia();
  EXPECT_NEAR(inertia, 0.5 * (0.025 * 0.025 + 0.3 * 0.3) / 12 + 0.5 * 0.15 * 0.15, 1e-12);  // 0.015026
  auto world = physics::MakeOdeWorld(rig.simulation().model().physics());
  physics::PhysicsParameters parameters;
  parameters.gravity = Eigen::Vector3d::Zero();
  const int joint = rig.joint();
  const double stiffness = 5.0;
  const double omega = std::sqrt(stiffness / inertia);
  world->SetJointMotor(joint, 0.5, 100.0);  // the kick
  ASSERT_EQ(world->Step(kDt, parameters), physics::StepStatus::kOk);
  std::vector<double> crossings;
  std::vector<double> peaks;
  double previous = world->joint_angle(joint);
  double before = 0.0;
  for (int i = 1; i < 200; ++i) {
    const double compliance = 1.0 / (stiffness * kDt);
    world->SetJointMotorCompliance(joint, compliance);
    world->SetJointMotor(joint, compliance * stiffness * (0.0 - world->joint_angle(joint)), 100.0);
    ASSERT_EQ(world->Step(kDt, parameters), physics::StepStatus::kOk);
    const double now = world->joint_angle(joint);
    if (previous < 0.0 && now >= 0.0) crossings.push_back((i + previous / (previous - now)) * kDt);
    if (i > 1 && previous > before && previous > now) peaks.push_back(previous);
    before = previous;
    previous = now;
  }
  ASSERT_GE(crossings.size(), 4u);
  ASSERT_GE(peaks.size(), 3u);
  const double measured = 2.0 * kPi / MeanPeriod(crossings);
  EXPECT_NEAR(measured, omega, 0.02 * omega);
  const double implicit = std::atan(omega * kDt) / kDt;
  EXPECT_NEAR(measured, implicit, 0.002 * implicit);
  // Per period the amplitude shrinks by (1 + (ω·dt)²)^(−T/(2·dt)), T = 2π/ω_implicit: 0.565.
  const double shrink = std::pow(1.0 + omega * kDt * omega * kDt, -kPi / (implicit * kDt));
  for (size_t k = 1; k < peaks.size(); ++k) EXPECT_NEAR(peaks[k] / peaks[k - 1], shrink, 0.03) << "peak " << k;
}

TEST_P(MotorEffectsRigTest, ElasticityMakesAFastStepRingYetTheOutputReachesTheTarget) {
  // A 20° step at full torque. The stiff motor brings the pole there without overshoot. Through a gear train of
  // 20 N·m/rad (ω = √(k/I) = 36 rad/s, a 0.17 s period) the pole overshoots (1.57°) and rings — it crosses the
  // target 12 times in 3 s — and still ends at the target, because the controller's sensor is on the output.
  const auto step = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(20.0);
    double highest = 0.0;
    int crossings = 0;
    double previous = 0.0;
    for (int i = 0; i < 300 && rig.Step(); ++i) {
      highest = std::max(highest, rig.Degrees());
      if (previous < 20.0 && rig.Degrees() >= 20.0) ++crossings;
      previous = rig.Degrees();
    }
    return std::tuple{highest - 20.0, crossings, rig.Degrees()};
  };
  const auto [overshoot_off, crossings_off, final_off] = step({});
  const auto [overshoot_on, crossings_on, final_on] =
      step(Effect("Elasticity", {{"/Effects/Elasticity/Stiffness", "20"}}));
  EXPECT_LT(overshoot_off, 1e-3);
  EXPECT_LE(crossings_off, 1);
  EXPECT_GT(overshoot_on, 0.4);
  EXPECT_GE(crossings_on, 3);
  EXPECT_NEAR(final_off, 20.0, 1e-3);
  // The compliant row is implicit on both engines (ODE's CFM, MuJoCo's row softness), so the ringing dies out.
  EXPECT_NEAR(final_on, 20.0, 0.01);
}

TEST_P(MotorEffectsRigTest, ElasticityOfAStiffGearTrainIsTheStiffMotor) {
  // The stiffer the gear train, the closer the joint comes to the stiff motor of the base model: with the default
  // stiffness (1e9 N·m/rad) the lift from hanging to 90° at full torque is the effect-off lift (measured: within
  // 1.1e-4°), and with the fit range's stiffest 200 N·m/rad it still passes 80° at the same 0.46 s. Before the fix
  // of ApplyElasticity the motor side could never wind further than max_torque/stiffness past the output's angle
  // before the step: the default stiffness froze the pole at 0° and 200 N·m/rad capped the lift at 0.5 rad/s.
  const auto lift = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(90.0);
    std::vector<double> angles;
    for (int i = 0; i < 150 && rig.Step(); ++i) angles.push_back(rig.Degrees());
    return angles;
  };
  const auto time_to_80 = [](const std::vector<double>& angles) {
    const auto at = std::find_if(angles.begin(), angles.end(), [](double angle) { return angle >= 80.0; });
    return static_cast<double>(at - angles.begin() + 1) * kDt;
  };
  const std::vector<double> off = lift({});
  const std::vector<double> stiff = lift(Effect("Elasticity", {}));
  const std::vector<double> firm = lift(Effect("Elasticity", {{"/Effects/Elasticity/Stiffness", "200"}}));
  ASSERT_EQ(stiff.size(), off.size());
  double largest = 0.0;
  for (size_t i = 0; i < off.size(); ++i) largest = std::max(largest, std::abs(stiff[i] - off[i]));
  EXPECT_LT(largest, 1e-3);  // degrees
  EXPECT_NEAR(time_to_80(off), 0.46, 0.005);
  EXPECT_NEAR(time_to_80(firm), time_to_80(off), 0.025);
  EXPECT_NEAR(firm.back(), 90.0, 0.01);
}

// ---------------------------------------------------------------------------------------------------------------
// RotorInertia

TEST_P(MotorEffectsRigTest, RotorInertiaLengthensTheFreeSwingPeriod) {
  // The pole released at 10° with the motor limp and no joint friction swings with T = 2π·√(I/(m·g·d))·(1 + A²/16)
  // (0.8996 s); a reflected rotor inertia J = 0.01 kg·m² lengthens that by √((I + J)/I) = 1.2906 — through the
  // effect, i.e. on the body the agent finds on the far side of the motor, about the motor's axis. Measured:
  // 0.89956 s and 1.16094 s, the ratio right to 1e-5; the bounds are 0.5 %.
  const auto period = [](const Values& values) {
    Values limp = values;
    limp.push_back({"/AngularMotor/StaticFriction", "0"});
    limp.push_back({"/AngularMotor/DynamicFriction", "0"});
    PendulumRig rig(limp, GetParam());
    rig.Pose(10.0);
    rig.Command(10.0, 0.0);
    return MeanPeriod(UpwardZeroCrossings(rig, 500));
  };
  const PendulumRig rig({}, GetParam());
  const double inertia = rig.Inertia();
  const double amplitude = 10.0 / kDegrees;
  const double expected = 2.0 * kPi * std::sqrt(inertia / rig.GravityTorque()) * (1.0 + amplitude * amplitude / 16);
  const double without = period({});
  const double with = period(Effect("RotorInertia", {{"/Effects/RotorInertia/Inertia", "0.01"}}));
  EXPECT_NEAR(without, expected, 0.005 * expected);
  const double ratio = std::sqrt((inertia + 0.01) / inertia);
  EXPECT_NEAR(with / without, ratio, 0.005 * ratio);
}

TEST_P(MotorEffectsRigTest, RotorInertiaSlowsATorqueLimitedStart) {
  // From rest at the bottom the motor starts a lift at its full torque 1.048 N·m (no load yet): after one step
  // the pole turns at τ·dt/I = 0.697 rad/s; with J = 0.01 kg·m² at τ·dt/(I + J), 0.600 of that (within 1 %).
  const auto first_rate = [](const Values& values) {
    PendulumRig rig(values, GetParam());
    rig.Command(90.0);
    rig.Step();
    return rig.Rate();
  };
  const double inertia = PendulumRig({}, GetParam()).Inertia();
  const double without = first_rate({});
  const double with = first_rate(Effect("RotorInertia", {{"/Effects/RotorInertia/Inertia", "0.01"}}));
  EXPECT_NEAR(without, kFullTorque * kDt / inertia, 0.01 * without);
  EXPECT_NEAR(with / without, inertia / (inertia + 0.01), 0.01 * inertia / (inertia + 0.01));
}

}  // namespace
}  // namespace orcs::aseries

namespace orcs::aseries {
namespace {

TEST(MotorEffectsTest, GearEfficiencyKeepsTheOutputGrowingUpToTheStallTorque) {
  // Friction μ·|τ| + q·τ² with q = Curvature·(1 − μ)/(2·τs): the output τ − friction grows with τ up to τs, and at
  // Curvature 1 levels off exactly there.
  MotorEffects effects;
  effects.efficiency_coefficient = 0.4;
  effects.efficiency_curvature = 1.0;
  const double stall = 1.2;
  EXPECT_NEAR(GearEfficiencyFriction(effects, 0.5, stall), 0.4 * 0.5 + 0.6 / 2.4 * 0.25, 1e-12);
  EXPECT_EQ(GearEfficiencyFriction(effects, -0.5, stall), GearEfficiencyFriction(effects, 0.5, stall));
  double previous = 0.0;
  for (double torque = 0.01; torque <= stall; torque += 0.01) {
    const double output = torque - GearEfficiencyFriction(effects, torque, stall);
    EXPECT_GE(output, previous) << torque;
    previous = output;
  }
  const auto slope_at = [&](double torque) {
    return (GearEfficiencyFriction(effects, torque + 1e-6, stall) - GearEfficiencyFriction(effects, torque, stall)) / 1e-6;
  };
  EXPECT_NEAR(slope_at(stall), 1.0, 1e-5) << "at the stall torque the friction takes all of a further newton-metre";
  effects.efficiency_curvature = 0.0;
  EXPECT_NEAR(GearEfficiencyFriction(effects, 0.5, stall), 0.2, 1e-12) << "no curvature: load friction";
}

}  // namespace
}  // namespace orcs::aseries
