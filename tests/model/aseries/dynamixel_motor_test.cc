#include "model/aseries/dynamixel_motor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "model/aseries/parameter_table.h"
#include "model/aseries/value_range.h"
#include "model/core/random_stream.h"
#include "model/core/variable_repository.h"

namespace orcs::aseries {
namespace {

constexpr double kDt = 0.01;
constexpr double kTight = 1e-12;

// Set A with a pure P controller of gain 1 and no velocity limit, so that v is the PID sum itself.
DynamixelParameters UnitGain() {
  DynamixelParameters parameters;
  parameters.kp = 1.0;
  parameters.max_velocity = -1.0;
  return parameters;
}

class DynamixelMotorTest : public ::testing::Test {
 protected:
  void SetUp() override { Reset(state_); }

  // One step with the joint at `angle` (rad) and the desired angle 0, so that the error is −angle.
  double VelocityForError(const DynamixelParameters& parameters, double error) {
    return Update(parameters, state_, -error, 0.0, kDefaultDesiredTorqueRaw, kDt, nullptr).velocity;
  }

  DynamixelState state_{};
};

TEST_F(DynamixelMotorTest, SetADefaults) {
  const DynamixelParameters p;
  EXPECT_EQ(p.kp, 20.0);
  EXPECT_EQ(p.ki, 0.0);
  EXPECT_EQ(p.kd, 0.0);
  EXPECT_EQ(p.history_size, 10);
  EXPECT_EQ(p.fmax_factor, 1.04803939);
  EXPECT_EQ(p.max_velocity, 3.5);
  EXPECT_EQ(p.static_friction, 0.001);
  EXPECT_EQ(p.static_friction_border, 0.1);
  EXPECT_EQ(p.dynamic_friction, 0.16);
  EXPECT_EQ(p.dynamic_friction_offset, 0.0);
  EXPECT_EQ(p.motor_noise, 0.0);
  EXPECT_TRUE(p.include_noise);
  EXPECT_FALSE(p.original_friction) << "the successor's friction form is the default";
  EXPECT_FALSE(p.torque_control) << "position control is the default";
}

TEST_F(DynamixelMotorTest, ProportionalTermWithSetA) {
  const DynamixelParameters set_a;
  // 10° = 0.17453292519943295 rad; Kp·e = 20 · 0.1745… = 3.490658503988659 rad/s, just below the 3.5 limit.
  EXPECT_NEAR(Update(set_a, state_, 0.0, 10.0, 0.5, kDt, nullptr).velocity, 3.490658503988659, kTight);
  // Joint at 0.1 rad, desired 0: e = −0.1, v = −2.
  EXPECT_NEAR(Update(set_a, state_, 0.1, 0.0, 0.5, kDt, nullptr).velocity, -2.0, kTight);
  EXPECT_NEAR(state_.velocity, -2.0, kTight);
  // Joint at −0.05 rad, desired −5° (−0.08726646259971647 rad): e = −0.03726646259971647, v = −0.7453292519943295.
  EXPECT_NEAR(Update(set_a, state_, -0.05, -5.0, 0.5, kDt, nullptr).velocity, -0.7453292519943295, kTight);
}

TEST_F(DynamixelMotorTest, VelocityIsClippedAtMaxVelocity) {
  const DynamixelParameters set_a;
  // 30°: Kp·e = 10.47 rad/s → 3.5; −30° → −3.5.
  EXPECT_EQ(Update(set_a, state_, 0.0, 30.0, 0.5, kDt, nullptr).velocity, 3.5);
  EXPECT_EQ(Update(set_a, state_, 0.0, -30.0, 0.5, kDt, nullptr).velocity, -3.5);
  // A negative MaxVelocity switches the limit off.
  DynamixelParameters unlimited;
  unlimited.max_velocity = -1.0;
  EXPECT_NEAR(Update(unlimited, state_, 0.0, 30.0, 0.5, kDt, nullptr).velocity, 10.471975511965976, 1e-11);
}

TEST_F(DynamixelMotorTest, DesiredAngleIsClampedTo150Degrees) {
  const DynamixelParameters p = UnitGain();
  // 200° → 150° = 2.6179938779914944 rad (unclamped would be 3.4906585…).
  EXPECT_NEAR(Update(p, state_, 0.0, 200.0, 0.5, kDt, nullptr).velocity, 2.6179938779914944, kTight);
  EXPECT_NEAR(Update(p, state_, 0.0, -1000.0, 0.5, kDt, nullptr).velocity, -2.6179938779914944, kTight);
  EXPECT_NEAR(Update(p, state_, 0.0, 150.0, 0.5, kDt, nullptr).velocity, 2.6179938779914944, kTight);
}

TEST_F(DynamixelMotorTest, IntegralSumsTheLastHistorySizeErrorsTimesDtOverKi) {
  DynamixelParameters p = UnitGain();
  p.ki = 0.5;  // dt/Ki = 0.02
  p.history_size = 3;
  // v = e + 0.02 · (sum of the last three errors).
  EXPECT_NEAR(VelocityForError(p, 0.1), 0.1 + 0.02 * 0.1, kTight);                // 0.102
  EXPECT_NEAR(VelocityForError(p, 0.2), 0.2 + 0.02 * 0.3, kTight);                // 0.206
  EXPECT_NEAR(VelocityForError(p, 0.3), 0.3 + 0.02 * 0.6, kTight);                // 0.312
  EXPECT_NEAR(VelocityForError(p, 0.4), 0.4 + 0.02 * (0.2 + 0.3 + 0.4), kTight);  // 0.418: 0.1 rolled out
  EXPECT_NEAR(VelocityForError(p, 0.5), 0.5 + 0.02 * (0.3 + 0.4 + 0.5), kTight);  // 0.524
  // A smaller history takes effect at once (the list drops its oldest entries) ...
  p.history_size = 1;
  EXPECT_NEAR(VelocityForError(p, 0.6), 0.6 + 0.02 * 0.6, kTight);  // 0.612
  // ... a larger one fills up again from what the list still holds.
  p.history_size = 3;
  EXPECT_NEAR(VelocityForError(p, 0.7), 0.7 + 0.02 * (0.6 + 0.7), kTight);        // 0.726
  EXPECT_NEAR(VelocityForError(p, 0.8), 0.8 + 0.02 * (0.6 + 0.7 + 0.8), kTight);  // 0.842
  // Reset empties the history.
  Reset(state_);
  EXPECT_NEAR(VelocityForError(p, 0.1), 0.102, kTight);
}

TEST_F(DynamixelMotorTest, IntegralIsAScaledSumNotATimeIntegral) {
  // The same errors with a ten times smaller dt give a ten times smaller I-part (dt/Ki · Σe), and Ki divides.
  DynamixelParameters p = UnitGain();
  p.ki = 2.0;
  p.history_size = 10;
  for (int i = 0; i < 4; ++i) Update(p, state_, -0.1, 0.0, 0.5, 0.001, nullptr);
  // Fifth error 0.1 with dt = 0.001: v = 0.1 + (0.001/2)·0.5 = 0.10025.
  EXPECT_NEAR(Update(p, state_, -0.1, 0.0, 0.5, 0.001, nullptr).velocity, 0.10025, kTight);
}

TEST_F(DynamixelMotorTest, HistorySizeIsClampedToCapacity) {
  DynamixelParameters p = UnitGain();
  p.ki = 1.0;  // dt/Ki = 0.01
  p.history_size = 1000;
  double velocity = 0.0;
  for (int i = 0; i < 100; ++i) velocity = VelocityForError(p, 0.5);
  EXPECT_NEAR(velocity, 0.5 + 0.01 * 0.5 * DynamixelParameters::kMaxHistory, kTight);
  p.history_size = 0;  // at least the current error
  EXPECT_NEAR(VelocityForError(p, 0.5), 0.5 + 0.01 * 0.5, kTight);
}

TEST_F(DynamixelMotorTest, TinyKiSwitchesTheIntegralOff) {
  DynamixelParameters p = UnitGain();
  p.ki = 1e-11;
  EXPECT_NEAR(VelocityForError(p, 0.3), 0.3, kTight);
  EXPECT_NEAR(VelocityForError(p, 0.3), 0.3, kTight);
  p.ki = -1e-11;
  EXPECT_NEAR(VelocityForError(p, 0.3), 0.3, kTight);
}

TEST_F(DynamixelMotorTest, DifferentialTerm) {
  DynamixelParameters p = UnitGain();
  p.kd = 0.05;  // Kd/dt = 5
  EXPECT_NEAR(VelocityForError(p, 0.1), 0.1 + 5 * 0.1, kTight);    // e_prev = 0 after Reset: 0.6
  EXPECT_NEAR(VelocityForError(p, 0.15), 0.15 + 5 * 0.05, kTight);  // 0.4
  EXPECT_NEAR(VelocityForError(p, 0.15), 0.15, kTight);              // no change, no D
  EXPECT_NEAR(VelocityForError(p, 0.05), 0.05 - 5 * 0.1, kTight);    // −0.45
  Reset(state_);
  EXPECT_NEAR(VelocityForError(p, 0.1), 0.6, kTight);
}

TEST_F(DynamixelMotorTest, PidTermsCombineBeforeTheClip) {
  DynamixelParameters p;  // Kp 20, MaxVelocity 3.5
  p.ki = 0.5;
  p.kd = 0.001;  // Kd/dt = 0.1
  p.history_size = 2;
  // e = 0.1: v = 20·(0.1 + 0.02·0.1 + 0.1·0.1) = 20·0.112 = 2.24
  EXPECT_NEAR(VelocityForError(p, 0.1), 2.24, kTight);
  // e = 0.2: v = 20·(0.2 + 0.02·0.3 + 0.1·0.1) = 20·0.216 = 4.32 → 3.5
  EXPECT_EQ(VelocityForError(p, 0.2), 3.5);
}

TEST_F(DynamixelMotorTest, FrictionBelowAndAboveTheStaticBorder) {
  const DynamixelParameters set_a;  // fs 0.001, bs 0.1, αd 0.16, od 0
  // ω = 0.0005/0.01 = 0.05 < 0.1: f = 0.001 + 0.16·0.05 = 0.009
  EXPECT_NEAR(Update(set_a, state_, 0.0005, 0.0, 0.5, kDt, nullptr).friction_torque, 0.009, kTight);
  // ω = (0.0025 − 0.0005)/0.01 = 0.2 ≥ 0.1: f = 0.16·0.2 = 0.032
  EXPECT_NEAR(Update(set_a, state_, 0.0025, 0.0, 0.5, kDt, nullptr).friction_torque, 0.032, kTight);
  // Moving backwards: ω = −0.2, same friction.
  EXPECT_NEAR(Update(set_a, state_, 0.0005, 0.0, 0.5, kDt, nullptr).friction_torque, 0.032, kTight);
  // Standing still: only static friction.
  EXPECT_NEAR(Update(set_a, state_, 0.0005, 0.0, 0.5, kDt, nullptr).friction_torque, 0.001, kTight);
}

TEST_F(DynamixelMotorTest, FrictionExactlyAtTheBorderIsDynamicOnly) {
  const DynamixelParameters set_a;
  // dt = 0.5 makes ω = 0.05/0.5 = 0.1 exactly: not below the border, so f = 0.16·0.1 = 0.016.
  EXPECT_NEAR(Update(set_a, state_, 0.05, 0.0, 0.5, 0.5, nullptr).friction_torque, 0.016, kTight);
}

TEST_F(DynamixelMotorTest, FrictionOffsetAndTheFloorAtZero) {
  DynamixelParameters p;
  p.dynamic_friction_offset = -0.05;
  // ω = 0.2: 0.032 − 0.05 < 0 → 0
  EXPECT_EQ(Update(p, state_, 0.002, 0.0, 0.5, kDt, nullptr).friction_torque, 0.0);
  // ω = (0.007 − 0.002)/0.01 = 0.5: 0.08 − 0.05 = 0.03
  EXPECT_NEAR(Update(p, state_, 0.007, 0.0, 0.5, kDt, nullptr).friction_torque, 0.03, kTight);
  p.dynamic_friction_offset = 0.02;
  // standing: 0.001 + 0.02
  EXPECT_NEAR(Update(p, state_, 0.007, 0.0, 0.5, kDt, nullptr).friction_torque, 0.021, kTight);
}

TEST_F(DynamixelMotorTest, OriginalFrictionFollowsTheSignedCommandWithAnInclusiveBorder) {
  DynamixelParameters p;  // fs 0.001, bs 0.1, αd 0.16
  p.dynamic_friction_offset = 0.2;
  // At the border: the original includes fs (|v| ≤ bs), the successor does not (|ω| < bs).
  EXPECT_NEAR(OriginalFriction(p, 0.1), 0.001 + 0.016 + 0.2, kTight);
  EXPECT_NEAR(SuccessorFriction(p, 0.1), 0.016 + 0.2, kTight);
  // Backwards: the original's αd·v is signed and lowers the brake; the successor's uses the speed.
  EXPECT_NEAR(OriginalFriction(p, -1.0), -0.16 + 0.2, kTight);
  EXPECT_NEAR(SuccessorFriction(p, -1.0), 0.16 + 0.2, kTight);
  EXPECT_EQ(OriginalFriction(p, -2.0), 0.0) << "−0.32 + 0.2 < 0: a hinge motor with FMax ≤ 0 brakes nothing";
}

TEST_F(DynamixelMotorTest, OriginalFrictionUsesTheCommandedNotTheMeasuredVelocity) {
  DynamixelParameters p;
  p.dynamic_friction_offset = 0.2;
  DynamixelState successor_state{};
  Reset(successor_state, 0.02);
  Reset(state_, 0.02);
  // The joint swings from 0.02 to 0 rad in one step (ω = −2 rad/s) onto its target: the command is v = 0.
  const DynamixelCommand successor = Update(p, successor_state, 0.0, 0.0, 0.5, kDt, nullptr);
  EXPECT_NEAR(successor.friction_torque, 0.16 * 2.0 + 0.2, kTight);
  p.original_friction = true;
  const DynamixelCommand original = Update(p, state_, 0.0, 0.0, 0.5, kDt, nullptr);
  EXPECT_EQ(original.velocity, 0.0);
  EXPECT_NEAR(original.friction_torque, 0.001 + 0.2, kTight);
  // Commanded towards 10° at v = 3.4906… rad/s (ProportionalTermWithSetA), with the joint at rest.
  const DynamixelCommand driven = Update(p, state_, 0.0, 10.0, 0.5, kDt, nullptr);
  EXPECT_NEAR(driven.friction_torque, 0.16 * driven.velocity + 0.2, kTight);
}

TEST_F(DynamixelMotorTest, TorqueControlPushesTowardsTheRangesEndWithTheSignedCommandAsItsLimit) {
  DynamixelParameters p;
  p.torque_control = true;
  // DesiredAngle (20°) is not used: the goal is +150° for a positive torque, so the PID asks for the velocity limit.
  const DynamixelCommand forward = Update(p, state_, 0.0, 20.0, 0.5, kDt, nullptr);
  EXPECT_EQ(forward.velocity, 3.5);
  EXPECT_NEAR(forward.max_torque, 1.04803939 * 0.5, kTight);
  // A negative torque is a torque the other way, not "no torque" as under position control.
  const DynamixelCommand backward = Update(p, state_, 0.0, 20.0, -0.25, kDt, nullptr);
  EXPECT_EQ(backward.velocity, -3.5);
  EXPECT_NEAR(backward.max_torque, 1.04803939 * 0.25, kTight);
  EXPECT_EQ(Update(p, state_, 0.0, 20.0, 0.0, kDt, nullptr).max_torque, 0.0) << "zero torque: limp";
  EXPECT_EQ(Update(p, state_, 0.0, 20.0, std::nan(""), kDt, nullptr).max_torque, 0.0) << "no command: limp";
  EXPECT_NEAR(Update(p, state_, 0.0, 20.0, -3.0, kDt, nullptr).max_torque, 1.04803939, kTight) << "clamped to −1";
  p.torque_control = false;
  EXPECT_EQ(Update(p, state_, 0.0, 20.0, -0.25, kDt, nullptr).max_torque, 0.0) << "position control: no torque";
}

TEST_F(DynamixelMotorTest, VelocityEstimateHasNoZeroCrossingSpecialCase) {
  const DynamixelParameters set_a;
  Reset(state_, 0.01);
  // 0.01 → −0.01 in 0.01 s: ω = −2 rad/s, f = 0.16·2 = 0.32 (the original's −(θ_prev + θ)/dt would give 0).
  EXPECT_NEAR(Update(set_a, state_, -0.01, 0.0, 0.5, kDt, nullptr).friction_torque, 0.32, kTight);
}

TEST_F(DynamixelMotorTest, ResetTakesTheCurrentAngleAsPreviousAngle) {
  const DynamixelParameters set_a;
  Reset(state_, 0.3);
  EXPECT_EQ(state_.previous_angle, 0.3);
  EXPECT_EQ(state_.previous_error, 0.0);
  EXPECT_EQ(state_.history_count, 0);
  // Not moving since the reset: only static friction.
  EXPECT_NEAR(Update(set_a, state_, 0.3, 0.0, 0.5, kDt, nullptr).friction_torque, 0.001, kTight);
  EXPECT_EQ(state_.previous_angle, 0.3);
}

TEST_F(DynamixelMotorTest, TorqueLimitIsFMaxFactorTimesPositiveDesiredTorque) {
  DynamixelParameters p;
  // The default desired torque: 1.04803939 · 0.586810005 = 0.614999999686097 N·m, from the first step on.
  EXPECT_NEAR(Update(p, state_, 0.0, 0.0, kDefaultDesiredTorqueRaw, kDt, nullptr).max_torque, 0.614999999686097,
              kTight);
  EXPECT_NEAR(state_.max_torque, 0.614999999686097, kTight);
  // Negative torque gives none.
  EXPECT_EQ(Update(p, state_, 0.0, 0.0, -0.5, kDt, nullptr).max_torque, 0.0);
  // Follows a change at once.
  EXPECT_NEAR(Update(p, state_, 0.0, 0.0, 1.0, kDt, nullptr).max_torque, 1.04803939, kTight);
  // Follows FMaxFactor at once, with the desired torque unchanged.
  p.fmax_factor = 2.0;
  EXPECT_NEAR(Update(p, state_, 0.0, 0.0, 1.0, kDt, nullptr).max_torque, 2.0, kTight);
  // Raw torque is clamped to its range −1…1.
  EXPECT_NEAR(Update(p, state_, 0.0, 0.0, 3.0, kDt, nullptr).max_torque, 2.0, kTight);
  EXPECT_EQ(TorqueLimit(p, 0.0), 0.0);
  EXPECT_NEAR(TorqueLimit(DynamixelParameters{}, 0.25), 0.2620098475, kTight);
}

TEST_F(DynamixelMotorTest, NormalisedTorqueAtOrBelowHalfGivesNoTorque) {
  const DynamixelParameters p;
  EXPECT_EQ(TorqueLimit(p, kDesiredTorqueRange.ToRaw(0.5)), 0.0);
  EXPECT_EQ(TorqueLimit(p, kDesiredTorqueRange.ToRaw(0.2)), 0.0);
  EXPECT_EQ(TorqueLimit(p, kDesiredTorqueRange.ToRaw(0.0)), 0.0);
  // n = 0.7934 → raw 0.5868 → 1.04803939 · 0.5868 N·m
  EXPECT_NEAR(TorqueLimit(p, kDesiredTorqueRange.ToRaw(0.7934)), 1.04803939 * 0.5868, kTight);
}

TEST_F(DynamixelMotorTest, NoiseSwitchedOffIsDeterministicAndDrawsNothing) {
  DynamixelParameters p;
  p.motor_noise = 0.5;
  p.include_noise = false;
  RandomStream stream(1, "motor-noise", 0);
  const RandomStream untouched = stream;
  EXPECT_NEAR(Update(p, state_, 0.0, 5.0, 0.5, kDt, &stream).velocity, 1.7453292519943295, kTight);
  RandomStream copy = untouched;
  EXPECT_EQ(stream.NextU64(), copy.NextU64());
  // No stream, or MotorNoise 0, is also noise-free.
  p.include_noise = true;
  EXPECT_NEAR(Update(p, state_, 0.0, 5.0, 0.5, kDt, nullptr).velocity, 1.7453292519943295, kTight);
  p.motor_noise = 0.0;
  EXPECT_NEAR(Update(p, state_, 0.0, 5.0, 0.5, kDt, &stream).velocity, 1.7453292519943295, kTight);
}

TEST_F(DynamixelMotorTest, NoiseIsAddedAfterTheClipAndIsReproducible) {
  DynamixelParameters p;
  p.motor_noise = 0.5;
  RandomStream stream(7, "motor-noise", 3);
  RandomStream expected = stream;
  // Clipped to 3.5 first, then the draw is added.
  EXPECT_DOUBLE_EQ(Update(p, state_, 0.0, 30.0, 0.5, kDt, &stream).velocity, 3.5 + expected.Normal(0.0, 0.5));
  EXPECT_DOUBLE_EQ(Update(p, state_, 0.0, 5.0, 0.5, kDt, &stream).velocity,
                   1.7453292519943295 + expected.Normal(0.0, 0.5));
}

TEST_F(DynamixelMotorTest, NoiseHasTheRightMeanAndDeviation) {
  DynamixelParameters p;
  p.motor_noise = 0.5;
  RandomStream stream(11, "motor-noise", 0);
  constexpr int kSamples = 20000;
  double sum = 0.0, sum_squares = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double v = Update(p, state_, 0.0, 0.0, 0.5, kDt, &stream).velocity;  // noise-free v = 0
    sum += v;
    sum_squares += v * v;
  }
  const double mean = sum / kSamples;
  const double deviation = std::sqrt(sum_squares / kSamples - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4 * 0.5 / std::sqrt(kSamples));
  EXPECT_NEAR(deviation, 0.5, 0.02 * 0.5);
}

TEST(ValueRangeTest, ExamplesOfSection4d) {
  EXPECT_NEAR(kDesiredTorqueRange.ToRaw(0.7934), 0.5868, kTight);
  EXPECT_EQ(kDesiredTorqueRange.ToRaw(0.5), 0.0);
  EXPECT_EQ(kDesiredTorqueRange.ToRaw(0.0), -1.0);
  EXPECT_EQ(kDesiredTorqueRange.ToRaw(1.0), 1.0);
  EXPECT_NEAR(kDesiredTorqueRange.ToNormalised(kDefaultDesiredTorqueRaw), 0.7934050025, kTight);
  EXPECT_EQ(kDesiredAngleRange.ToRaw(1.0), 150.0);
  EXPECT_EQ(kDesiredAngleRange.ToRaw(-0.5), -75.0);
  EXPECT_EQ(kDesiredAngleRange.ToNormalised(75.0), 0.5);
  EXPECT_EQ(kJointAngleRange.ToNormalised(-150.0), -1.0);
  EXPECT_EQ(kJointAngleRange.ToRaw(0.0), 0.0);
  // 1 g is 1/1.6384 of the accelerometer range.
  EXPECT_NEAR(kAccelAxisRange.ToNormalised(-9.81), -0.6103515625, kTight);
  EXPECT_NEAR(kAccelAxisRange.ToRaw(1.0), 16.072704, kTight);
}

TEST(ValueRangeTest, ValuesOutsideTheRangeAreClamped) {
  EXPECT_EQ(kDesiredAngleRange.ToRaw(2.0), 150.0);
  EXPECT_EQ(kDesiredAngleRange.ToNormalised(-200.0), -1.0);
  EXPECT_EQ(kDesiredTorqueRange.ToRaw(-0.5), -1.0);
  EXPECT_EQ(kAccelAxisRange.ToNormalised(100.0), 1.0);
  EXPECT_EQ(kDesiredAngleRange.ClampRaw(151.0), 150.0);
}

TEST(ValueRangeTest, RoundTrips) {
  for (const ValueRange& range : {kDesiredAngleRange, kDesiredTorqueRange, kJointAngleRange, kAccelAxisRange}) {
    for (double n = range.norm_min; n <= range.norm_max + 1e-12; n += (range.norm_max - range.norm_min) / 16) {
      EXPECT_NEAR(range.ToNormalised(range.ToRaw(n)), n, kTight);
    }
    for (double raw = range.raw_min; raw <= range.raw_max + 1e-9; raw += (range.raw_max - range.raw_min) / 16) {
      EXPECT_NEAR(range.ToRaw(range.ToNormalised(raw)), raw, 1e-11);
    }
  }
}

TEST(DynamixelParameterTableTest, RegistersSetAAndReadsChanges) {
  VariableRepository repository;
  AddParameters(repository, kDynamixelParameterTable);
  ASSERT_EQ(repository.size(), 14);
  EXPECT_EQ(repository.Get("/AngularMotor/PID/Proportional").as_double(), 20.0);
  EXPECT_EQ(repository.Get("/AngularMotor/PID/HistorySize").as_int(), 10);
  EXPECT_EQ(repository.Get("/AngularMotor/FMaxFactor").as_double(), 1.04803939);
  EXPECT_TRUE(repository.Get("/AngularMotor/IncludeNoise").as_bool());

  repository.Set("/AngularMotor/PID/Integral", "18.25");
  repository.Set("/AngularMotor/PID/HistorySize", "4");
  repository.Set("/AngularMotor/IncludeNoise", "F");
  repository.Set("/AngularMotor/DynamicFrictionOffset", "0.19");
  repository.Set("/AngularMotor/OriginalFriction", "T");
  DynamixelParameters parameters;
  ReadParameters(repository, kDynamixelParameterTable, parameters);
  EXPECT_EQ(parameters.ki, 18.25);
  EXPECT_EQ(parameters.history_size, 4);
  EXPECT_FALSE(parameters.include_noise);
  EXPECT_EQ(parameters.dynamic_friction_offset, 0.19);
  EXPECT_TRUE(parameters.original_friction);
  EXPECT_EQ(parameters.kp, 20.0);

  // Registering again keeps the current values (first registration wins).
  AddParameters(repository, kDynamixelParameterTable);
  EXPECT_EQ(repository.Get("/AngularMotor/PID/Integral").as_double(), 18.25);
  EXPECT_EQ(repository.size(), 14);
}

}  // namespace
}  // namespace orcs::aseries
