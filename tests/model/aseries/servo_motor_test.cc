// The physical servo model (model/aseries/servo_motor.h, docs/model.md "The physical servo"): the firmware's
// duty law in isolation, the DC motor's torque-speed line as the compliant motor row gives it, and on the driven
// pendulum rig (both engines) what the physics must show: the pole held where the motor's torque at the given
// firmware gain balances gravity, the torque-speed line during a fast swing, and a limp servo swinging freely.
#include "model/aseries/servo_motor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "model/aseries/motor_effects.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "tests/model/aseries/pendulum_rig.h"

namespace orcs::aseries {
namespace {

constexpr double kDt = 0.01;  // s, the rig's step
constexpr double kDegrees = 180.0 / std::numbers::pi;

// The XL330-M288 of scenarios/values/servo_xl330.val at the pendulum log's 7.4 V.
ServoParameters Xl330() {
  ServoParameters servo;
  servo.enabled = true;
  servo.firmware_kp = 400.0;
  servo.kp_scale = 0.00575481;
  servo.supply_voltage = 7.4;
  servo.resistance = 3.401;
  servo.torque_constant = 0.3537;
  servo.back_emf_constant = 0.4635;
  servo.armature = 0.0;
  servo.coulomb_friction = 0.0;
  servo.viscous_friction = 0.0;
  return servo;
}

double ExpectedStall(const ServoParameters& s) { return s.torque_constant * s.supply_voltage / s.resistance; }

TEST(ServoMotorTest, DutyIsTheGainTimesTheErrorClippedToThePwmLimitTimesTheTorqueEnable) {
  ServoParameters servo = Xl330();
  EXPECT_NEAR(ServoDuty(servo, 0.1, 0.0, 0.0, 1.0), 400.0 * 0.00575481 * 0.1, 1e-12);
  EXPECT_NEAR(ServoDuty(servo, -0.1, 0.0, 0.0, 1.0), -400.0 * 0.00575481 * 0.1, 1e-12);
  EXPECT_EQ(ServoDuty(servo, 2.0, 0.0, 0.0, 1.0), 1.0) << "clipped to full duty";
  servo.firmware_kp = 100.0;
  EXPECT_NEAR(ServoDuty(servo, 0.1, 0.0, 0.0, 1.0), 100.0 * 0.00575481 * 0.1, 1e-12) << "the gain is an input";
  servo.pwm_limit = 0.5;
  EXPECT_EQ(ServoDuty(servo, -3.0, 0.0, 0.0, 0.6), -0.3) << "PWM limit × torque enable";
  EXPECT_EQ(ServoDuty(servo, 3.0, 0.0, 0.0, 0.0), 0.0) << "torque off";
  EXPECT_EQ(ServoDuty(servo, 3.0, 0.0, 0.0, -1.0), 0.0) << "a negative torque is off, not reversed";
  EXPECT_EQ(ServoDuty(servo, 3.0, 0.0, 0.0, std::numeric_limits<double>::quiet_NaN()), 0.0);
  servo.pwm_limit = 1.0;
  servo.firmware_ki = 2.0;
  servo.ki_scale = 0.01;
  servo.firmware_kd = 3.0;
  servo.kd_scale = 0.001;
  EXPECT_NEAR(ServoDuty(servo, 0.1, 0.5, -2.0, 1.0), 100.0 * 0.00575481 * 0.1 + 2.0 * 0.01 * 0.5 - 3.0 * 0.001 * 2.0,
              1e-12);
}

TEST(ServoMotorTest, TheMotorRowYieldsAlongTheDcMotorsTorqueSpeedLine) {
  // The engine ends the step at the rate u = velocity − compliance·τ; solved for τ that must be the DC motor's
  // kt·(V·duty − ke·u)/R at every end rate, and within the row's bound.
  const ServoParameters servo = Xl330();
  for (const double rate : {0.0, 3.0, -5.0}) {
    DynamixelState state;
    Reset(state, 0.0);
    const ServoCommand command = ServoUpdate(servo, state, 0.0, rate, 5.0, 1.0, kDt);
    const double duty = 400.0 * 0.00575481 * 5.0 / kDegrees;
    ASSERT_NEAR(command.duty, duty, 1e-12);
    for (const double end_rate : {rate - 1.0, rate, rate + 1.0}) {
      const double torque = (command.motor.velocity - end_rate) / command.compliance;
      const double dc_motor = servo.torque_constant * (servo.supply_voltage * duty - servo.back_emf_constant * end_rate) /
                              servo.resistance;
      EXPECT_NEAR(torque, dc_motor, 1e-9) << rate << " → " << end_rate;
      EXPECT_LT(std::abs(torque), command.motor.max_torque);
    }
  }
}

// A warm winding has a higher resistance (copper: 0.393 % per kelvin), so the same duty gives less torque and the
// back-EMF brakes less; at the reference temperature the resistance is exactly the one given.
TEST(ServoMotorTest, AWarmWindingHasTheCopperResistanceAndGivesLessTorque) {
  ServoParameters servo = Xl330();
  EXPECT_EQ(WindingResistance(servo), servo.resistance) << "25 °C, the reference";
  const double cold_stall = StallTorque(servo);
  servo.winding_temperature = 35.0;
  EXPECT_NEAR(WindingResistance(servo), 3.401 * (1.0 + 0.00393 * 10.0), 1e-12);
  EXPECT_NEAR(StallTorque(servo), cold_stall / (1.0 + 0.0393), 1e-12);
  DynamixelState state;
  Reset(state, 0.0);
  const ServoCommand command = ServoUpdate(servo, state, 0.0, 2.0, 5.0, 1.0, kDt);
  const double duty = 400.0 * 0.00575481 * 5.0 / kDegrees;
  const double torque = (command.motor.velocity - 2.0) / command.compliance;
  EXPECT_NEAR(torque, servo.torque_constant * (7.4 * duty - servo.back_emf_constant * 2.0) / WindingResistance(servo),
              1e-9);
  servo.reference_temperature = 35.0;
  EXPECT_EQ(WindingResistance(servo), servo.resistance) << "the resistance is given at the reference";
  servo.resistance_temperature_coefficient = 0.0;
  servo.winding_temperature = 80.0;
  EXPECT_EQ(WindingResistance(servo), servo.resistance) << "no coefficient, no change";
}

TEST(ServoMotorTest, ALimpServoHasNoMotorOnlyTheGearboxFriction) {
  ServoParameters servo = Xl330();
  servo.coulomb_friction = 0.02;
  servo.viscous_friction = 0.01;
  DynamixelState state;
  Reset(state, 0.0);
  const ServoCommand limp = ServoUpdate(servo, state, 0.0, -2.0, 60.0, 0.0, kDt);
  EXPECT_EQ(limp.motor.max_torque, 0.0);
  EXPECT_EQ(limp.compliance, 0.0);
  EXPECT_EQ(limp.duty, 0.0);
  EXPECT_NEAR(limp.motor.friction_torque, 0.02 + 0.01 * 2.0, 1e-12);
}

TEST(ServoMotorTest, TheIntegralDoesNotWindUpWhileTheDutyIsClipped) {
  ServoParameters servo = Xl330();
  servo.firmware_ki = 1.0;
  servo.ki_scale = 0.1;
  DynamixelState state;
  Reset(state, 0.0);
  for (int i = 0; i < 100; ++i) ServoUpdate(servo, state, 0.0, 0.0, 90.0, 1.0, kDt);  // duty clipped throughout
  EXPECT_EQ(state.error_integral, 0.0);
  for (int i = 0; i < 10; ++i) ServoUpdate(servo, state, 0.0, 0.0, 0.5, 1.0, kDt);  // within the linear range
  EXPECT_NEAR(state.error_integral, 10 * kDt * 0.5 / kDegrees, 1e-12);
}

TEST(ServoMotorTest, ElasticityCannotCombineWithTheServoMode) {
  MotorEffects effects;
  effects.elasticity = true;
  EXPECT_NO_THROW(CheckEffectsFitServo(ServoParameters{}, effects));
  try {
    CheckEffectsFitServo(Xl330(), effects);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/Effects/Elasticity/Enabled"), std::string::npos) << error.what();
  }
}

TEST(ServoMotorTest, TheCurrentLimitBoundsTheMotorsTorqueAtKtTimesTheLimit) {
  // A large error asks for full duty: 7.4 V / 3.401 Ω = 2.18 A at rest. The firmware's current limit caps the
  // winding current, so the torque the row can give and the torque the load frictions see are kt × the limit.
  ServoParameters servo = Xl330();
  const double unlimited = ExpectedStall(servo);
  for (const double limit : {0.0, 1.0}) {
    servo.current_limit = limit;
    for (const double goal : {60.0, -60.0}) {
      DynamixelState state;
      Reset(state, 0.0);
      const ServoCommand command = ServoUpdate(servo, state, 0.0, 0.0, goal, 1.0, kDt);
      const double expected = limit > 0.0 ? servo.torque_constant * limit : unlimited;
      EXPECT_NEAR(command.torque, std::copysign(expected, goal), 1e-12) << "limit " << limit << " A";
      if (limit > 0.0) {
        EXPECT_NEAR(command.motor.max_torque, expected, 1e-12);
      }
      EXPECT_GE(command.motor.max_torque, expected - 1e-12);
    }
  }
}

TEST(ServoMotorTest, TheLoadFrictionsTakeThisStepsMotorTorqueNotTheLastOnes) {
  // The DC motor's torque is known before the step: kt·(V·duty − ke·ω)/R with this step's duty. LoadFriction,
  // GearEfficiency and BackDrive take it, whatever the last step's was (docs/model.md, "The physical servo").
  const ServoParameters servo = Xl330();
  const double rate = 0.5;  // rad/s, with the motor: not back-driven
  const double duty = 400.0 * 0.00575481 * 10.0 / kDegrees;
  const double torque = servo.torque_constant * (7.4 * duty - servo.back_emf_constant * rate) / servo.resistance;
  for (const double last : {0.0, -0.8}) {
    MotorEffects effects;
    effects.load_friction = true;
    effects.load_coefficient = 0.3;
    effects.gear_efficiency = true;
    effects.efficiency_coefficient = 0.2;
    effects.efficiency_curvature = 0.5;
    effects.back_drive = true;
    effects.back_drive_coefficient = 0.4;
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(state, 0.0);
    ResetEffects(memory, 0.0);
    const EffectCommand command = UpdateWithEffects(DynamixelParameters{}, servo, effects, state, memory,
                                                    {0.0, rate, last}, 10.0, 1.0, kDt, nullptr);
    EXPECT_NEAR(command.motor.friction_torque,
                0.3 * torque + GearEfficiencyFriction(effects, torque, StallTorque(servo)), 1e-12)
        << "last step's torque " << last << " (a back-driven gear would add BackDrive's share)";
  }
}

TEST(ServoMotorTest, GravityLoadFrictionGrowsWithTheLoadsPullAgainstTheMotor) {
  // BAM's load-dependent friction (M3): c·|τg − τ|, τ this step's motor torque. Holding a load (τ = −τg) the mesh
  // carries twice the hold; a motor pushing the way gravity pulls carries only their difference.
  const ServoParameters servo = Xl330();
  const double duty = 400.0 * 0.00575481 * 10.0 / kDegrees;
  const double torque = servo.torque_constant * 7.4 * duty / servo.resistance;  // at rest
  MotorEffects effects;
  effects.gravity_load_friction = true;
  effects.gravity_load_coefficient = 0.25;
  for (const double gravity : {-torque, torque, 0.0}) {
    DynamixelState state{};
    MotorEffectState memory{};
    Reset(state, 0.0);
    ResetEffects(memory, 0.0);
    const EffectCommand command = UpdateWithEffects(DynamixelParameters{}, servo, effects, state, memory,
                                                    {0.0, 0.0, 0.0, gravity}, 10.0, 1.0, kDt, nullptr);
    EXPECT_NEAR(command.motor.friction_torque, 0.25 * std::abs(gravity - torque), 1e-12) << "gravity " << gravity;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// On the pendulum rig, both engines

class ServoRigTest : public ::testing::TestWithParam<const char*> {};

Values ServoValues(const ServoParameters& s) {
  return {{"/Servo/Enabled", "true"},
          {"/Servo/FirmwareKp", text::FormatDouble(s.firmware_kp)},
          {"/Servo/KpScale", text::FormatDouble(s.kp_scale)},
          {"/Servo/SupplyVoltage", text::FormatDouble(s.supply_voltage)},
          {"/Servo/Resistance", text::FormatDouble(s.resistance)},
          {"/Servo/TorqueConstant", text::FormatDouble(s.torque_constant)},
          {"/Servo/BackEmfConstant", text::FormatDouble(s.back_emf_constant)},
          {"/Servo/Armature", text::FormatDouble(s.armature)},
          {"/Servo/CoulombFriction", text::FormatDouble(s.coulomb_friction)},
          {"/Servo/ViscousFriction", text::FormatDouble(s.viscous_friction)}};
}

// Where stall·clip(kp·scale·(goal − θ)) = m·g·d·sin θ, by bisection on θ ∈ [0, goal].
double Equilibrium(const ServoParameters& s, double gravity_torque, double goal_rad) {
  double low = 0.0;
  double high = goal_rad;
  for (int i = 0; i < 100; ++i) {
    const double theta = 0.5 * (low + high);
    const double motor = ExpectedStall(s) * std::min(1.0, s.firmware_kp * s.kp_scale * (goal_rad - theta));
    (motor > gravity_torque * std::sin(theta) ? low : high) = theta;
  }
  return 0.5 * (low + high);
}

TEST_P(ServoRigTest, HoldsThePoleWhereTheMotorAtTheFirmwareGainBalancesGravity) {
  // No friction: the pole settles where the motor's torque at its duty equals gravity's. The lower gain needs a
  // larger error for the same torque, so it holds the pole lower — the firmware gain is an input of the run.
  ServoParameters servo = Xl330();
  servo.viscous_friction = 0.05;  // N·m·s/rad, only to let it settle; no force at rest
  for (const double gain : {100.0, 400.0}) {
    servo.firmware_kp = gain;
    PendulumRig rig(ServoValues(servo), GetParam());
    rig.Command(60.0, 1.0);
    ASSERT_TRUE(rig.Run(600));
    const double expected = Equilibrium(servo, rig.GravityTorque(), 60.0 / kDegrees) * kDegrees;
    EXPECT_NEAR(rig.Degrees(), expected, 0.2) << "gain " << gain;
    EXPECT_LT(std::abs(rig.Rate()), 1e-3) << "settled";
  }
}

TEST_P(ServoRigTest, AFullDutySwingFollowsTheTorqueSpeedLine) {
  // Commanded far away, the duty is 1 (up to 25° before the goal: 400 × 0.00575 × 0.436 rad): every step's motor
  // torque lies on kt·(V − ke·ω)/R at that step's end rate, while the pole speeds up beyond 3 rad/s (where
  // back-EMF has taken more than a third of the stall torque).
  const ServoParameters servo = Xl330();
  PendulumRig rig(ServoValues(servo), GetParam());
  rig.Command(150.0, 1.0);
  double fastest = 0.0;
  for (int i = 0; i < 60 && rig.Degrees() < 120.0; ++i) {
    ASSERT_TRUE(rig.Step());
    const double rate = rig.Rate();
    const double line = servo.torque_constant * (servo.supply_voltage - servo.back_emf_constant * rate) / servo.resistance;
    EXPECT_NEAR(rig.simulation().physics().joint_motor_torque(rig.joint()), line, 0.01 * ExpectedStall(servo))
        << "step " << i << " at " << rate << " rad/s";
    fastest = std::max(fastest, rate);
  }
  EXPECT_GT(fastest, 3.0);
}

TEST_P(ServoRigTest, ALimpServoLetsThePoleSwingFreelyAndArmatureSlowsIt) {
  // Torque off (DesiredTorque 0) and no friction: released at 30° the pole swings to about −30°. Its period grows
  // with the armature as √((I + A)/I).
  const auto swing = [&](double armature) {
    ServoParameters servo = Xl330();
    servo.armature = armature;
    PendulumRig rig(ServoValues(servo), GetParam());
    rig.Pose(30.0);
    rig.Command(30.0, 0.0);
    double lowest = 30.0;
    int steps_to_lowest = 0;
    for (int i = 1; i <= 300 && rig.Step() && !(i > 1 && rig.Rate() > 0.0); ++i) {  // until it turns back
      lowest = rig.Degrees();
      steps_to_lowest = i;
    }
    return std::pair{lowest, steps_to_lowest * kDt};
  };
  PendulumRig probe({}, GetParam());
  const double inertia = probe.Inertia();
  const auto [lowest, half_period] = swing(0.0);
  EXPECT_NEAR(lowest, -30.0, 0.6) << "no motor, no friction: a free swing";
  const auto [lowest_heavy, half_period_heavy] = swing(inertia);  // twice the inertia
  EXPECT_NEAR(lowest_heavy, -30.0, 0.6);
  EXPECT_NEAR(half_period_heavy / half_period, std::sqrt(2.0), 0.05);
}

TEST_P(ServoRigTest, LoadFrictionTakesThisStepsTorqueSoACoarseStepIsAsCloseToAFineOneAsWithoutIt) {
  // The pole tracks a 1 Hz sine at firmware gain 400 with gearbox friction that grows with the transmitted torque
  // (GearEfficiency as fitted to the XL330), once at the logs' 5 ms steps and once at 1 ms sub-steps. The two
  // differ because the firmware runs five times as often, and without the effect by about 0.4° RMS. With it they
  // must differ no more: the friction takes this step's motor torque. The last step's, 5 ms old, added a quarter
  // to a third to the difference.
  const auto rms_difference = [&](bool gear_efficiency) {
    const auto run = [&](double step, int iterations) {
      ServoParameters servo = Xl330();
      servo.torque_constant = 0.43;
      servo.armature = 0.0019;
      servo.coulomb_friction = 0.017;
      servo.viscous_friction = 0.011;
      Values values = ServoValues(servo);
      values.push_back({"/Simulation/TimeStepSize", text::FormatDouble(step)});
      values.push_back({"/Simulation/IterationsPerStep", std::to_string(iterations)});
      values.push_back({"/Effects/GearEfficiency/Enabled", gear_efficiency ? "true" : "false"});
      values.push_back({"/Effects/GearEfficiency/Coefficient", "0.43"});
      values.push_back({"/Effects/GearEfficiency/Curvature", "0.3"});
      PendulumRig rig(values, GetParam());
      std::vector<double> trace;  // degrees, every 5 ms
      for (int row = 0; row < 600; ++row) {
        rig.Command(50.0 * std::sin(2.0 * std::numbers::pi * row * 0.005), 1.0);
        if (!rig.Step()) break;
        trace.push_back(rig.Degrees());
      }
      return trace;
    };
    const std::vector<double> coarse = run(0.005, 1);
    const std::vector<double> fine = run(0.001, 5);
    EXPECT_EQ(coarse.size(), 600u);
    EXPECT_EQ(fine.size(), 600u);
    EXPECT_GT(*std::max_element(fine.begin(), fine.end()), 30.0) << "the pole follows the sine";
    double squares = 0.0;
    for (std::size_t k = 0; k < std::min(coarse.size(), fine.size()); ++k) {
      squares += (coarse[k] - fine[k]) * (coarse[k] - fine[k]);
    }
    return std::sqrt(squares / static_cast<double>(coarse.size()));
  };
  const double without = rms_difference(false);
  EXPECT_GT(without, 0.1) << "the firmware's rate alone makes the runs differ";
  EXPECT_LT(rms_difference(true), 1.1 * without);
}

TEST_P(ServoRigTest, ACurrentLimitLetsThePoleSagToWhereKtTimesTheLimitHoldsGravity) {
  // Commanded to 80° at gain 400 the duty is full long before the goal; with 0.8 A × kt = 0.28 N·m the motor can
  // hold the pole only where m·g·d·sin θ is that much, well below the goal. Without the limit it holds near 80°.
  ServoParameters servo = Xl330();
  servo.viscous_friction = 0.05;  // N·m·s/rad, only to let it settle
  for (const double limit : {0.0, 0.8}) {
    servo.current_limit = limit;
    Values values = ServoValues(servo);
    values.push_back({"/Servo/CurrentLimit", text::FormatDouble(limit)});
    PendulumRig rig(values, GetParam());
    rig.Command(80.0, 1.0);
    ASSERT_TRUE(rig.Run(600));
    const double hold = limit > 0.0 ? std::asin(servo.torque_constant * limit / rig.GravityTorque()) * kDegrees
                                    : Equilibrium(servo, rig.GravityTorque(), 80.0 / kDegrees) * kDegrees;
    EXPECT_NEAR(rig.Degrees(), hold, 0.3) << "limit " << limit << " A";
    EXPECT_LT(std::abs(rig.Rate()), 1e-3) << "settled";
  }
}

TEST_P(ServoRigTest, GravityLoadFrictionStopsALiftWhereTheNetTorqueFallsToItsShareOfTheMeshLoad) {
  // Lifted slowly, the motor's torque τ > 0 and gravity's −m·g·d·sin θ pull against each other: the mesh carries
  // τ + m·g·d·sin θ and the friction c times that brakes the lift where τ − m·g·d·sin θ falls to it, i.e. where
  // τ·(1 − c) = m·g·d·sin θ·(1 + c), well short of the frictionless hold. Gravity's torque on the load, computed
  // from the pole's pose, must have the joint angle's sense for this: with the wrong sign the friction would be
  // c·|τ − m·g·d·sin θ|, nearly 0 there, and the pole would rise to the frictionless hold.
  ServoParameters servo = Xl330();
  servo.firmware_kp = 100.0;
  servo.viscous_friction = 0.05;
  constexpr double kCoefficient = 0.3;
  const auto rest = [&](bool effect) {
    Values values = ServoValues(servo);
    values.push_back({"/Effects/GravityLoadFriction/Enabled", effect ? "true" : "false"});
    values.push_back({"/Effects/GravityLoadFriction/Coefficient", text::FormatDouble(kCoefficient)});
    PendulumRig rig(values, GetParam());
    for (int step = 1; step <= 400; ++step) {  // a slow ramp: the pole creeps up and stops with no momentum
      rig.Command(60.0 * step / 400.0, 1.0);
      EXPECT_TRUE(rig.Step());
    }
    EXPECT_TRUE(rig.Run(300));
    EXPECT_LT(std::abs(rig.Rate()), 1e-3) << "settled";
    return std::pair{rig.Degrees(), rig.GravityTorque()};
  };
  const auto [free_hold, weight] = rest(false);
  const double goal = 60.0 / kDegrees;
  double low = 0.0;
  double high = goal;
  for (int i = 0; i < 100; ++i) {  // the first angle where the lift stalls
    const double theta = 0.5 * (low + high);
    const double motor = ExpectedStall(servo) * std::min(1.0, servo.firmware_kp * servo.kp_scale * (goal - theta));
    (motor * (1.0 - kCoefficient) > weight * std::sin(theta) * (1.0 + kCoefficient) ? low : high) = theta;
  }
  const double stall = 0.5 * (low + high) * kDegrees;
  EXPECT_NEAR(free_hold, Equilibrium(servo, weight, goal) * kDegrees, 0.2);
  EXPECT_LT(stall, free_hold - 5.0) << "the friction must matter for the test to mean anything";
  EXPECT_NEAR(rest(true).first, stall, 0.5);
}

TEST_P(ServoRigTest, TheServoModeRefusesElasticityWithAClearMessage) {
  Values values = ServoValues(Xl330());
  values.push_back({"/Effects/Elasticity/Enabled", "true"});
  PendulumRig rig(values, GetParam());
  try {
    rig.Step();
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/Servo/Enabled"), std::string::npos) << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Engines, ServoRigTest, ::testing::Values("ODE", "MuJoCo"),
                         [](const ::testing::TestParamInfo<const char*>& engine) { return std::string(engine.param); });

}  // namespace
}  // namespace orcs::aseries
